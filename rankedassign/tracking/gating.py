"""Spatial gating and clusters: which tracks can see which measurements, in near-linear time.

The χ² gate of a Gaussian component ``c`` (predicted mean ``m_c``, innovation covariance
``S_c = H P_c Hᵀ + R``) is the ellipse ``{z : (z − H m_c)ᵀ S_c⁻¹ (z − H m_c) <= γ}``. It lies
inside the disc of radius ``√(γ λ_max(S_c))`` about ``H m_c``, because
``νᵀ S⁻¹ ν >= |ν|² / λ_max(S)``. So a k-d tree of the scan's measurements
(:class:`scipy.spatial.cKDTree`), queried with that disc for every component, returns every pair
that can pass the gate, and the exact χ² test then runs on those candidates only: the tree
prunes, it never decides. With bounded gates (a few measurements each) this costs
``O((C + M) log M)`` instead of the ``O(C M)`` of the dense gate
(:func:`rankedassign.tracking._kernels.gate_and_distances`).

The exact test repeats the dense kernel's arithmetic operation by operation (the closed-form
2 x 2 inverse and ``i00 ν0² + (i01 + i10) ν0 ν1 + i11 ν1²`` in that order), so a pair passes
here exactly when it passes there.

Clusters (:func:`clusters`) are the connected components of the bipartite graph of tracks and
measurements joined by gated pairs, found by :func:`scipy.sparse.csgraph.connected_components`
in ``O(T + M + pairs)``: tracks of different clusters share no measurement, so their association
problems are independent (spec §6.5a; Beard, Vo & Vo 2020).

References
----------
.. [1] M. Beard, B.-T. Vo, B.-N. Vo, "A Solution for Large-Scale Multi-Object Tracking", IEEE
   Trans. Signal Process. 68:2754-2769, 2020.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

__all__ = ["GatedPairs", "Clusters", "gate_radii", "candidate_pairs", "gate_pairs",
           "sensor_candidate_pairs", "track_pairs", "clusters", "dense_gate"]

#: Relative widening of the bounding disc: the rounding of ``λ_max`` and of the exact test is
#: some 1e-15, so a pair the exact test accepts is never pruned by the tree.
RADIUS_SLACK = 1e-6


class GatedPairs(NamedTuple):
    """The track–measurement pairs inside the χ² gate.

    Attributes
    ----------
    track, meas : ndarray of int64, shape (E,)
        The pairs, sorted by track then measurement, without repeats (a pair passes when some
        component of the track passes).
    n_tracks, n_meas : int
        ``T`` and ``M``, the sizes of the graph.
    n_candidates : int
        Component–measurement pairs the tree returned (the exact test's work).
    """

    track: np.ndarray
    meas: np.ndarray
    n_tracks: int
    n_meas: int
    n_candidates: int


class Clusters(NamedTuple):
    """Connected components of the gated track–measurement graph.

    Attributes
    ----------
    track_cluster : ndarray of int64, shape (T,)
        Cluster of every track; clusters are numbered in the order of their first track.
    meas_cluster : ndarray of int64, shape (M,)
        Cluster of every measurement, ``-1`` for a measurement no track gates.
    n_clusters : int
        Number of clusters (every track is in one; a track gating nothing is alone).
    """

    track_cluster: np.ndarray
    meas_cluster: np.ndarray
    n_clusters: int

    def groups(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Every cluster as ``(rows, cols)``: sorted int64 track and measurement indices.

        Returns
        -------
        list of (ndarray, ndarray)
            In cluster order (that of :func:`rankedassign.tracking.group_tracks`).
        """
        n = self.n_clusters
        rows = _split_by(self.track_cluster, n)
        cols = _split_by(self.meas_cluster, n)
        return list(zip(rows, cols, strict=True))


def _split_by(label: np.ndarray, n: int) -> list[np.ndarray]:
    """Indices of each label ``0..n−1`` (sorted), by one stable sort: ``O(K log K)``."""
    order = np.argsort(label, kind="stable")
    lab = label[order]
    keep = lab >= 0
    order, lab = order[keep], lab[keep]
    bounds = np.searchsorted(lab, np.arange(n + 1))
    return [order[bounds[g]:bounds[g + 1]].astype(np.int64) for g in range(n)]


def _innovation_inverse(P: np.ndarray, R: np.ndarray):
    """``S = H P Hᵀ + R`` entries, ``|S|`` and the closed-form inverse, as the dense kernel."""
    s00 = P[:, 0, 0] + R[0, 0]
    s01 = P[:, 0, 2] + R[0, 1]
    s10 = P[:, 2, 0] + R[1, 0]
    s11 = P[:, 2, 2] + R[1, 1]
    d = s00 * s11 - s01 * s10
    # a singular S gives inf/nan as the compiled kernel does (no warning there either); such a
    # component's radius is inf and its exact test fails as the kernel's does
    with np.errstate(divide="ignore", invalid="ignore"):
        return (s00, s01, s10, s11), d, (s11 / d, -s01 / d, -s10 / d, s00 / d)


def gate_radii(P: np.ndarray, R: np.ndarray, gate: float) -> np.ndarray:
    """Radius of the disc about ``H m_c`` that holds component ``c``'s χ² gate.

    Parameters
    ----------
    P : ndarray, shape (C, 4, 4)
        Predicted covariances (state ``[p_x, v_x, p_y, v_y]``).
    R : ndarray, shape (2, 2)
        Measurement noise covariance.
    gate : float
        Threshold ``γ`` on the squared Mahalanobis distance.

    Returns
    -------
    ndarray, shape (C,)
        ``√(γ λ_max(S_c)) (1 + RADIUS_SLACK)``; ``inf`` where ``S_c`` is not a finite positive
        definite matrix (every measurement is then a candidate and the exact test decides).

    Examples
    --------
    >>> import numpy as np
    >>> gate_radii(np.zeros((1, 4, 4)), 4.0 * np.eye(2), 9.0).round(3).tolist()
    [6.0]
    """
    (s00, s01, s10, s11), d, _ = _innovation_inverse(np.asarray(P, dtype=np.float64),
                                                     np.asarray(R, dtype=np.float64))
    # λ_max of the symmetric part (ν' S⁻¹ ν only sees the symmetric part of S⁻¹)
    b = 0.5 * (s01 + s10)
    half_tr = 0.5 * (s00 + s11)
    lam = half_tr + np.hypot(0.5 * (s00 - s11), b)
    with np.errstate(invalid="ignore"):
        r = np.sqrt(gate * lam) * (1.0 + RADIUS_SLACK)
    bad = ~(np.isfinite(r) & (d > 0) & (s00 > 0))
    r[bad] = np.inf
    return r


def candidate_pairs(centres: np.ndarray, radii: np.ndarray, z: np.ndarray,
                    tree: cKDTree | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Every (component, measurement) pair whose distance is at most the component's radius.

    Parameters
    ----------
    centres : ndarray, shape (C, 2)
        Predicted measurement positions ``H m_c``.
    radii : ndarray, shape (C,)
        Radii (:func:`gate_radii`); ``inf`` takes every measurement.
    z : ndarray, shape (M, 2)
        The scan's measurements.
    tree : cKDTree, optional
        A tree already built on ``z``.

    Returns
    -------
    comp, meas : ndarray of int64, shape (K,)
        The candidate pairs, sorted by component then measurement.

    Examples
    --------
    >>> import numpy as np
    >>> c, j = candidate_pairs(np.zeros((2, 2)), np.array([1.5, 0.5]),
    ...                        np.array([[1.0, 0.0], [3.0, 0.0]]))
    >>> c.tolist(), j.tolist()
    ([0], [0])
    """
    C = centres.shape[0]
    M = z.shape[0]
    if C == 0 or M == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    finite = np.isfinite(radii)
    comp_parts, meas_parts = [], []
    if finite.any():
        tree = cKDTree(z) if tree is None else tree
        idx = np.flatnonzero(finite)
        hits = tree.query_ball_point(centres[idx], r=radii[idx], return_sorted=False)
        lens = np.fromiter((len(h) for h in hits), dtype=np.int64, count=idx.size)
        comp_parts.append(np.repeat(idx, lens))
        meas_parts.append(np.fromiter((j for h in hits for j in h), dtype=np.int64,
                                      count=int(lens.sum())))
    inf_idx = np.flatnonzero(~finite)
    if inf_idx.size:
        comp_parts.append(np.repeat(inf_idx, M))
        meas_parts.append(np.tile(np.arange(M, dtype=np.int64), inf_idx.size))
    comp = np.concatenate(comp_parts)
    meas = np.concatenate(meas_parts)
    order = np.lexsort((meas, comp))
    return comp[order], meas[order]


def gate_pairs(m: np.ndarray, P: np.ndarray, R: np.ndarray, z: np.ndarray,
               offsets: np.ndarray, gate: float) -> GatedPairs:
    """The exact χ² gate of every track and measurement, computed on spatial candidates only.

    Parameters
    ----------
    m, P : ndarray, shapes (C, 4) and (C, 4, 4)
        Predicted component means and covariances.
    R : ndarray, shape (2, 2)
        Measurement noise covariance (``H`` picks ``p_x, p_y``).
    z : ndarray, shape (M, 2)
        Measurements.
    offsets : ndarray of int64, shape (T + 1,)
        Component range of every track.
    gate : float
        Threshold on the squared Mahalanobis distance.

    Returns
    -------
    GatedPairs
        The pairs where some component of the track passes, exactly those of the ``gated``
        matrix of :func:`rankedassign.tracking._kernels.gate_and_distances`.

    Examples
    --------
    >>> import numpy as np
    >>> g = gate_pairs(np.zeros((1, 4)), np.zeros((1, 4, 4)), np.eye(2),
    ...                np.array([[1.0, 1.0], [9.0, 0.0]]), np.array([0, 1]), 9.0)
    >>> g.track.tolist(), g.meas.tolist()
    ([0], [0])
    """
    m = np.asarray(m, dtype=np.float64)
    P = np.asarray(P, dtype=np.float64)
    R = np.asarray(R, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    offsets = np.asarray(offsets, dtype=np.int64)
    M = z.shape[0]
    comp, meas = candidate_pairs(m[:, [0, 2]], gate_radii(P, R, gate), z)
    n_cand = int(comp.size)
    if n_cand:
        _, _, (i00, i01, i10, i11) = _innovation_inverse(P, R)
        i00, i01, i10, i11 = i00[comp], i01[comp], i10[comp], i11[comp]
        cross = i01 + i10
        n0 = z[meas, 0] - m[comp, 0]
        n1 = z[meas, 1] - m[comp, 2]
        # ν' S⁻¹ ν, term by term in the dense kernel's order
        with np.errstate(invalid="ignore"):
            q = i00 * (n0 * n0) + cross * n0 * n1 + i11 * (n1 * n1)
        ok = q <= gate
        comp, meas = comp[ok], meas[ok]
    return track_pairs(comp, meas, offsets, M, n_cand)


def sensor_candidate_pairs(zhat: np.ndarray, S: np.ndarray, z: np.ndarray, gate: float,
                           angles: np.ndarray, scale: np.ndarray
                           ) -> tuple[np.ndarray, np.ndarray]:
    """Every (component, measurement) pair that can pass the χ² gate, in a sensor's own
    coordinates (e.g. bearing and range).

    The measurements are indexed in the scaled coordinates ``z_d / scale_d``, with a periodic
    axis of length ``2π / scale_d`` for every angle (:class:`scipy.spatial.cKDTree`'s
    ``boxsize``), so that a bearing near ``+π`` is near one near ``−π``. In scaled coordinates
    the innovation is ``D ν`` (``D = diag(1/scale)``) with covariance ``D S D``, and the gate
    ``νᵀ S⁻¹ ν <= γ`` lies inside the disc of radius ``√(γ λ_max(D S D))`` about ``D ẑ``
    (widened by :data:`RADIUS_SLACK`); the tree's periodic distance is that of the wrapped
    innovation. The tree prunes; the caller's exact test decides
    (:meth:`rankedassign.tracking.nonlinear.step.SingleObject.gate_pairs`).

    Parameters
    ----------
    zhat : ndarray, shape (C, d_z)
        Predicted measurements.
    S : ndarray, shape (C, d_z, d_z)
        Innovation covariances.
    z : ndarray, shape (M, d_z)
        Measurements.
    gate : float
        Threshold ``γ`` on the squared Mahalanobis distance.
    angles : ndarray of bool, shape (d_z,)
        Which coordinates are angles (periodic, ``2π``).
    scale : ndarray, shape (d_z,)
        Positive scale of every coordinate (the sensor's noise standard deviations make the
        gates about round).

    Returns
    -------
    comp, meas : ndarray of int64, shape (K,)
        The candidate pairs, sorted by component then measurement.

    Examples
    --------
    A bearing of ``+3.14`` rad is 0.18° from one of ``−3.14`` rad, across ``±π``:

    >>> import numpy as np
    >>> S = np.diag([0.01**2, 10.0**2])[None]
    >>> c, j = sensor_candidate_pairs(np.array([[3.14, 500.0]]), S,
    ...                               np.array([[-3.14, 505.0], [3.14, 900.0]]), 32.2,
    ...                               np.array([True, False]), np.array([0.01, 10.0]))
    >>> c.tolist(), j.tolist()
    ([0], [0])
    """
    zhat = np.asarray(zhat, dtype=np.float64)
    S = np.asarray(S, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    angles = np.asarray(angles, dtype=bool)
    scale = np.asarray(scale, dtype=np.float64)
    if zhat.shape[0] == 0 or z.shape[0] == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    # λ_max of the symmetric part of D S D (ν' S⁻¹ ν only sees the symmetric part)
    Ss = S / np.multiply.outer(scale, scale)
    with np.errstate(invalid="ignore"):
        lam = np.linalg.eigvalsh(0.5 * (Ss + Ss.transpose(0, 2, 1)))[:, -1]
        radii = np.sqrt(gate * lam) * (1.0 + RADIUS_SLACK)
    radii[~np.isfinite(radii)] = np.inf
    box = np.where(angles, 2.0 * np.pi / scale, 0.0)  # 0: not periodic

    def scaled(x):
        x = x / scale
        if angles.any():
            a = np.mod(x[:, angles], box[angles])
            # mod may round up to the box's length itself, which cKDTree refuses
            x[:, angles] = np.where(a >= box[angles], 0.0, a)
        return x

    tree = cKDTree(scaled(z), boxsize=box if angles.any() else None)
    return candidate_pairs(scaled(zhat), radii, z, tree=tree)


def track_pairs(comp: np.ndarray, meas: np.ndarray, offsets: np.ndarray, n_meas: int,
                n_candidates: int) -> GatedPairs:
    """The track–measurement pairs of gated component–measurement pairs.

    Parameters
    ----------
    comp, meas : ndarray of int64, shape (K,)
        Component–measurement pairs that passed the gate.
    offsets : ndarray of int64, shape (T + 1,)
        Component range of every track.
    n_meas : int
        ``M``.
    n_candidates : int
        Pairs the exact test ran on.

    Returns
    -------
    GatedPairs
        A pair where some component of the track passed, sorted, without repeats.

    Examples
    --------
    >>> import numpy as np
    >>> g = track_pairs(np.array([0, 1, 2]), np.array([1, 1, 0]), np.array([0, 2, 3]), 2, 5)
    >>> g.track.tolist(), g.meas.tolist()
    ([0, 1], [1, 0])
    """
    offsets = np.asarray(offsets, dtype=np.int64)
    M = max(int(n_meas), 1)
    track = np.searchsorted(offsets, comp, side="right") - 1
    if track.size:
        key = np.unique(track * M + meas)
        track, meas = key // M, key % M
    return GatedPairs(np.asarray(track, np.int64), np.asarray(meas, np.int64),
                      offsets.size - 1, int(n_meas), int(n_candidates))


def dense_gate(pairs: GatedPairs) -> np.ndarray:
    """The ``(T, M)`` boolean gate matrix of ``pairs`` (for tests and small scenes).

    Parameters
    ----------
    pairs : GatedPairs

    Returns
    -------
    ndarray of bool, shape (T, M)

    Examples
    --------
    >>> import numpy as np
    >>> dense_gate(GatedPairs(np.array([1]), np.array([0]), 2, 1, 1)).tolist()
    [[False], [True]]
    """
    g = np.zeros((pairs.n_tracks, pairs.n_meas), dtype=bool)
    g[pairs.track, pairs.meas] = True
    return g


def clusters(pairs: GatedPairs) -> Clusters:
    """Tracks linked through shared gated measurements, by connected components.

    Parameters
    ----------
    pairs : GatedPairs
        The gated pairs (:func:`gate_pairs`, or the nonzeros of a dense gate).

    Returns
    -------
    Clusters
        The same partition and numbering as the dense
        :func:`rankedassign.tracking._kernels.connected_groups`: clusters in the order of
        their first track, ``-1`` for a measurement no track gates.

    Examples
    --------
    >>> import numpy as np
    >>> p = GatedPairs(np.array([0, 1, 2]), np.array([0, 2, 0]), 4, 3, 3)
    >>> c = clusters(p)
    >>> c.track_cluster.tolist(), c.meas_cluster.tolist(), c.n_clusters
    ([0, 1, 0, 2], [0, -1, 1], 3)
    """
    T, M = pairs.n_tracks, pairs.n_meas
    if T == 0:
        return Clusters(np.empty(0, np.int64), np.full(M, -1, np.int64), 0)
    # nodes 0..T-1 are tracks, T..T+M-1 measurements
    graph = coo_matrix((np.ones(pairs.track.size, dtype=np.int8), (pairs.track, T + pairs.meas)),
                       shape=(T + M, T + M)).tocsr()
    _, lab = connected_components(graph, directed=False)
    lab = lab.astype(np.int64)
    # renumber by first track (every track has a label; a lone measurement's is dropped)
    uniq, first = np.unique(lab[:T], return_index=True)
    rank = np.empty(uniq.size, dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(uniq.size)
    renum = np.full(int(lab.max()) + 1, -1, dtype=np.int64)
    renum[uniq] = rank
    track_cluster = renum[lab[:T]]
    meas_cluster = renum[lab[T:]]
    # a measurement alone in its component got the label of no track: -1 already
    return Clusters(track_cluster, meas_cluster, int(uniq.size))

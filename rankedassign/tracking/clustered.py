"""The clustered δ-GLMB filter (Beard, Vo & Vo 2020): independent δ-GLMBs, one per cluster.

The posterior is held as a product of δ-GLMB densities over disjoint sets of labels, the
*clusters*; each is a :class:`~rankedassign.tracking.GLMBFilter` state of its own (track table,
components, weights). One scan of :class:`ClusteredGLMBFilter`:

1. gate (:func:`~rankedassign.tracking.gating.gate_pairs`): every entry of every cluster,
   predicted, and every birth of the scan against the measurements, through a k-d tree;
2. group the labels: labels (and births) linked through a shared gated measurement are one
   group (connected components, :func:`~rankedassign.tracking.gating.clusters`);
3. split: a cluster whose labels fall in several groups is marginalised onto each group's
   labels (``w'(I ∩ L_g) = Σ_{I' : I' ∩ L_g = I ∩ L_g} w(I')``), the one approximation of the
   scheme (the correlation between its parts is dropped);
4. merge: the parts of a group form one cluster, the product of their δ-GLMBs (weights
   ``w_a w_b``, sets ``I_a ∪ I_b``), capped at ``h_max`` components (the dropped mass is in
   the record); births join the group their gates touch (a birth that gates nothing starts a
   cluster of its own);
5. each cluster runs one scan of the δ-GLMB filter on its own measurements with its own budget
   ``h_upd``, ``h_max`` and truncation, from a child random stream keyed by the scan's key and
   the cluster's smallest label, so the result does not depend on the order in which the
   clusters are processed;
6. clusters left without a track are dropped; the estimate is the union of the clusters'
   estimates, the cardinality distribution the convolution of theirs, and the retained mass of
   the scene the product of the clusters' (spec §4: ``K`` and ``Z`` factorise over independent
   clusters), each by the oracle's DP where it reaches.

When every label stays in one group the scheme is the δ-GLMB filter itself (no split, no
merge): :class:`ClusteredGLMBFilter` then gives :class:`GLMBFilter`'s numbers (a test holds
them to 1e-12 with a deterministic truncation; the random streams differ by construction).

References
----------
.. [1] M. Beard, B.-T. Vo, B.-N. Vo, "A Solution for Large-Scale Multi-Object Tracking", IEEE
   Trans. Signal Process. 68:2754-2769, 2020.
.. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.
"""

from __future__ import annotations

import copy
import math
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from time import perf_counter

import numpy as np

from ..engine.rng import spawning_generator
from ..validation import MAX_WORK_BYTES, check_int, check_type
from .common import check_measurements as _check_measurements
from .gating import GatedPairs, clusters, gate_pairs
from .models import Model
from .nonlinear.vo import NonlinearModel
from .protocol import record_base
from .single.glmb import GLMBFilter

__all__ = ["CLUSTER_WORK_BYTES", "PAIR_BYTES", "ClusteredGLMBFilter", "ClusteredScanRecord"]

_TWO63 = 2**63
#: Bytes a cluster's scan holds per (Gaussian component, measurement) pair of its dense terms
#: (innovations 16, distances 8, log-weights 8, and the per-track cost, weight and gate arrays
#: of the δ-GLMB scan), rounded up.
PAIR_BYTES = 64
#: Largest work a cluster's terms may take: a scene whose gates join so many labels and
#: measurements into one cluster is refused before the allocation, with the size it would need.
CLUSTER_WORK_BYTES = MAX_WORK_BYTES


def _size(n_bytes: float) -> str:
    """``n_bytes`` in binary units, e.g. ``'3.5 GiB'``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if n_bytes < 1024 or unit == "TiB":
            return f"{n_bytes:.1f} {unit}" if unit != "B" else f"{int(n_bytes)} B"
        n_bytes /= 1024
    raise AssertionError  # pragma: no cover


class ClusteredScanRecord(record_base(
        "ClusteredScanRecord", cardinality=np.ndarray, n_components=int, retained_mass=float,
        retained_mass_reason=str, trajectories=tuple, n_clusters=int, cluster_sizes=np.ndarray,
        cluster_retained_mass=np.ndarray, cluster_scanned_sizes=np.ndarray, n_merges=int,
        n_splits=int, merge_dropped_mass=float)):
    """What :class:`ClusteredGLMBFilter` reports for one scan.

    The first fields are those of :class:`~rankedassign.tracking.GLMBScanRecord`, for the
    scene (counters summed over the clusters).

    Attributes
    ----------
    labels, states, existence : ndarray
        The reported tracks of every cluster, in increasing label order.
    track_labels, track_existence : ndarray
        Every label held with ``r(ℓ)``, in increasing label order.
    n_tracks : int
        Entries of the clusters' predicted tables (births included).
    n_meas, n_meas_gated : int
        Measurements received and measurements some entry gates.
    n_groups : int
        Problems solved (components, summed over the clusters).
    invocations, sweeps, row_updates, n_unique : int
        Association accounting summed over the clusters.
    timings : dict
        Seconds in ``prediction`` (with the gate and the regrouping), ``cost``,
        ``association``, ``update``.
    cardinality : ndarray
        The scene's ``ρ(n)``, the convolution of the clusters'.
    n_components : int
        Components held, summed over the clusters (the product's count is their product).
    retained_mass : float
        Product of the clusters' retained masses that the DP reached (NaN when not computed).
    retained_mass_reason : str
        Why ``retained_mass`` is NaN, or which clusters it leaves out ("" when none).
    trajectories : tuple
        Always empty (the clusters keep no whole histories).
    n_clusters : int
        Clusters after the scan.
    cluster_sizes : ndarray of int64, shape (n_clusters,)
        Labels per cluster after the scan (clusters in increasing order of their smallest
        label).
    cluster_retained_mass : ndarray, shape (n_clusters_scanned,)
        Each scanned cluster's retained mass (NaN where not computed or beyond the DP).
    cluster_scanned_sizes : ndarray of int64
        Labels per scanned cluster (births included), the same order.
    n_merges, n_splits : int
        Clusters formed from several parts, clusters marginalised into several parts.
    merge_dropped_mass : float
        Largest weight mass one product dropped at the ``h_max`` cap this scan (0 when no cap
        applied).
    """

    __slots__ = ()  # no instance dict: a plain named tuple, fields from record_base


class _Cluster(GLMBFilter):
    """A δ-GLMB filter over one cluster of labels, given the births it takes at each scan."""

    _birth_sel = np.empty(0, dtype=np.int64)
    #: The distinct label keys of the table after the last scan (increasing), or None.
    _ukeys = None
    #: ``(m, P)`` of the table predicted one scan on, as the scan's gate computed them (the
    #: scan then uses them instead of predicting again), or None.
    _pred = None

    def _predict(self) -> np.ndarray:
        """:meth:`GLMBFilter._predict` with the births ``_birth_sel`` only (their labels
        ``(k, b + 1)`` as the unclustered filter gives them)."""
        self.k += 1
        T_old = self.n_tracks
        sel = self._birth_sel
        if self._pred is not None:  # the gate's prediction of this very table
            self.m, self.P = self._pred
            self._pred = None
        else:
            self.m, self.P = _predicted(self, self.m, self.P)
        B = sel.size
        if B == 0:  # most clusters of a large scene take no birth: nothing to append
            self._births = np.empty(0, dtype=np.int64)
            return np.full(T_old, self._ps)
        labels = np.empty((B, 2), dtype=np.int64)
        labels[:, 0] = self.k
        labels[:, 1] = sel + 1
        self.labels = np.concatenate([self.labels, labels])
        n, comp = _birth_components(self, sel)
        self.offsets = np.concatenate([self.offsets, self.w.size + np.cumsum(n)])
        self.w = np.concatenate([self.w, self._birth_weights()[comp]])
        self.m = np.ascontiguousarray(np.concatenate([self.m, self._birth_m[comp]]))
        self.P = np.ascontiguousarray(np.concatenate([self.P, self._birth_P[comp]]))
        self.hist = np.concatenate([self.hist, np.full(B, -1, dtype=np.int64)])
        self._births = np.arange(T_old, T_old + B, dtype=np.int64)
        return np.concatenate([np.full(T_old, self._ps), self._birth_r[sel]])

    def _append_nodes(self, parents, meas, states) -> np.ndarray:
        """The scan's history nodes, alone: a cluster keeps no histories (every parent is
        −1), so no entry reaches an older node and what :meth:`GLMBFilter._compact_history`
        would leave of the forest is the new nodes; kept without growing the arrays scan by
        scan."""
        n = parents.size
        self._node_parent = parents
        self._node_scan = np.full(n, self.k, np.int64)
        self._node_meas = meas
        self._node_state = states
        self._live_nodes = n
        return np.arange(n, dtype=np.int64)

    def _birth_weights(self) -> np.ndarray:
        """Weights of the birth terms' Gaussians (one Gaussian of weight 1 a term, or the
        non-linear model's mixtures)."""
        return np.ones(self._birth_r.size) if self._so is None else self._so.birth_w


def _predicted(c: GLMBFilter, m: np.ndarray, P: np.ndarray):
    """``m``, ``P`` one scan on by the motion of ``c`` (``F m``, ``F P Fᵀ + Q``, or the
    non-linear model's filter)."""
    if c._so is not None:
        return c._so.predict(m, P)
    return m @ c._F.T, c._F @ P @ c._F.T + c._Q


def _birth_components(c: GLMBFilter, sel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Gaussians of the birth terms ``sel``: their counts and their indices (in order)."""
    if c._so is None:  # one Gaussian a term
        return np.ones(sel.size, dtype=np.int64), sel
    counts = c._so.birth_counts
    off = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    comp, n = _segments(off, np.arange(int(off[-1])), sel)
    return n, comp


def _label_keys(labels: np.ndarray) -> np.ndarray:
    """One int64 per label ``(scan, index)``, ordered as the labels."""
    return labels[:, 0] * (1 << 32) + labels[:, 1]


def _segments(off: np.ndarray, vals: np.ndarray, sel: np.ndarray):
    """The CSR segments ``sel`` of ``(off, vals)``, concatenated, and their lengths."""
    n = off[sel + 1] - off[sel]
    start = np.cumsum(n) - n
    idx = np.repeat(off[sel] - start, n) + np.arange(int(n.sum()))
    return vals[idx], n


def _store_components(c: _Cluster, off: np.ndarray, tracks: np.ndarray,
                      weights: np.ndarray) -> None:
    """Store the components ``(off, tracks)`` (CSR) with ``weights`` in ``c``, heaviest first
    (ties in the given order) and normalised: the δ-GLMB filter reads its components heaviest
    first."""
    order = np.argsort(-weights, kind="stable")
    vals, n = _segments(off, tracks, order)
    c.comp_off = np.concatenate([[0], np.cumsum(n)]).astype(np.int64)
    c.comp_tracks = vals.astype(np.int64)
    w = weights[order]
    c.comp_w = w / w.sum()


def _sorted_components(c: _Cluster, sets: list, weights: np.ndarray) -> None:
    """:func:`_store_components` of components given as lists of entry indices."""
    sizes = np.array([len(x) for x in sets], dtype=np.int64)
    tracks = (np.concatenate([np.asarray(x, dtype=np.int64) for x in sets])
              if sizes.sum() else np.empty(0, dtype=np.int64))
    _store_components(c, np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64), tracks,
                      weights)


def _keep_entries(c: _Cluster, keep: np.ndarray) -> np.ndarray:
    """Restrict the track table of ``c`` to entries ``keep`` (bool); returns the old → new
    index map (−1 for a dropped entry). Components are not touched."""
    new_index = np.cumsum(keep) - 1
    new_index[~keep] = -1
    n = np.diff(c.offsets)[keep]
    starts = c.offsets[:-1][keep]
    comp = np.repeat(starts - (np.cumsum(n) - n), n) + np.arange(int(n.sum()))
    c.offsets = np.concatenate([[0], np.cumsum(n)]).astype(np.int64)
    c.w, c.m, c.P = c.w[comp], c.m[comp], c.P[comp]
    c.labels = c.labels[keep]
    nodes = c.hist[keep]
    # histories are not kept (keep_histories=False): one node per entry, its last scan
    c._node_parent = np.full(nodes.size, -1, dtype=np.int64)
    c._node_scan = c._node_scan[nodes]
    c._node_meas = c._node_meas[nodes]
    c._node_state = c._node_state[nodes]
    c.hist = np.arange(nodes.size, dtype=np.int64)
    c._live_nodes = int(nodes.size)
    return new_index


def _marginal(c: _Cluster, label_keep: np.ndarray) -> _Cluster:
    """The δ-GLMB of ``c`` marginalised onto its labels where ``label_keep`` (per entry)."""
    part = copy.copy(c)
    part._ukeys = None
    part._pred = None  # a part predicts its own table (the same numbers as it always did)
    new_index = _keep_entries(part, label_keep)
    acc: dict = {}
    for h in range(c.n_components):
        ents = c.comp_tracks[c.comp_off[h]:c.comp_off[h + 1]]
        key = tuple(new_index[ents[label_keep[ents]]].tolist())
        acc[key] = acc.get(key, 0.0) + float(c.comp_w[h])
    sets = list(acc)
    _sorted_components(part, [list(s) for s in sets], np.array([acc[s] for s in sets]))
    return part


def _product(a: _Cluster, b: _Cluster, cap: int) -> tuple[_Cluster, float]:
    """The product of two independent δ-GLMBs over disjoint labels, its ``cap`` heaviest
    components kept; returns it and the weight mass the cap dropped."""
    out = copy.copy(a)
    out._ukeys = None
    out._pred = None
    Ta = a.n_tracks
    out.labels = np.concatenate([a.labels, b.labels])
    out.offsets = np.concatenate([a.offsets, b.offsets[1:] + a.w.size])
    out.w = np.concatenate([a.w, b.w])
    out.m = np.ascontiguousarray(np.concatenate([a.m, b.m]))
    out.P = np.ascontiguousarray(np.concatenate([a.P, b.P]))
    n_nodes = a._node_parent.size
    out.hist = np.concatenate([a.hist, b.hist + n_nodes])
    out._node_parent = np.concatenate([a._node_parent,
                                       np.where(b._node_parent >= 0, b._node_parent + n_nodes,
                                                -1)])
    out._node_scan = np.concatenate([a._node_scan, b._node_scan])
    out._node_meas = np.concatenate([a._node_meas, b._node_meas])
    out._node_state = np.concatenate([a._node_state, b._node_state])
    out._live_nodes = a._live_nodes + b._live_nodes
    out._confirmed = np.union1d(a._confirmed, b._confirmed)
    # w_(i, j) = w_i w_j; the cap keeps the heaviest pairs
    w = np.outer(a.comp_w, b.comp_w).reshape(-1)
    if w.size > cap:
        # the pairs kept in their own order: ties at the cap do not depend on the partition
        top = np.sort(np.argpartition(-w, cap - 1)[:cap])
        dropped = float(1.0 - w[top].sum())
    else:
        top = np.arange(w.size)
        dropped = 0.0
    i, j = np.divmod(top, b.n_components)
    # the set of pair (i, j): I_i, then I_j with b's entries after a's
    va, na = _segments(a.comp_off, a.comp_tracks, i)
    vb, nb = _segments(b.comp_off, b.comp_tracks + Ta, j)
    n = na + nb
    start = np.cumsum(n) - n
    tracks = np.empty(int(n.sum()), dtype=np.int64)
    tracks[np.repeat(start, na) + np.arange(va.size) - np.repeat(np.cumsum(na) - na, na)] = va
    tracks[np.repeat(start + na, nb) + np.arange(vb.size) - np.repeat(np.cumsum(nb) - nb, nb)] = vb
    _store_components(out, np.concatenate([[0], np.cumsum(n)]).astype(np.int64), tracks, w[top])
    return out, max(dropped, 0.0)


def _scan_clusters(tasks: list) -> list:
    """One scan of every ``(cluster, measurements, stream key)`` task: ``(cluster, record)``."""
    return [(c, c._scan(z, np.random.default_rng(key))) for c, z, key in tasks]


def _convolve_all(dists: list[np.ndarray]) -> np.ndarray:
    """The distribution of a sum of independent counts: a pairwise tree of convolutions."""
    if not dists:
        return np.ones(1)
    while len(dists) > 1:
        nxt = [np.convolve(dists[i], dists[i + 1]) for i in range(0, len(dists) - 1, 2)]
        if len(dists) % 2:
            nxt.append(dists[-1])
        dists = nxt
    return dists[0]


class ClusteredGLMBFilter:
    """δ-GLMB filter kept as independent δ-GLMBs over clusters of labels (Beard et al. 2020).

    Parameters
    ----------
    model : Model or NonlinearModel
        As :class:`~rankedassign.tracking.GLMBFilter`; with a
        :class:`~rankedassign.tracking.nonlinear.NonlinearModel` (e.g. the ``"large"``
        scenario's bearing–range sensor) the entries are gated in the sensor's own coordinates
        (:meth:`~rankedassign.tracking.nonlinear.step.SingleObject.gate_pairs`).
    association : object
        The truncation of every cluster's components (any truncation
        :class:`~rankedassign.tracking.GLMBFilter` takes).
    gate_prob : float, optional
        χ² gate probability (default ``1 − 10⁻⁷``); the clusters are defined by this gate, so
        it cannot be None.
    h_upd, h_max : int, optional
        Each cluster's budget and cap (default 1000 each), and the cap of a merge's product.
    extraction : {"map", "hysteresis"} or None, optional
        Each cluster's extraction (None: the model's). ``"trajectory"`` is refused (the
        clusters keep no whole histories across merges).
    retained_mass : bool, optional
        Compute each cluster's retained mass with the oracle's DP and the scene's product.
    workers : int, optional
        Processes that run the clusters' scans (default 1: in this process). Each cluster's
        scan depends only on its own state, measurements and stream, so the numbers are the
        same for any ``workers``; the states travel to the workers and back by pickling, so
        it pays only when the clusters' scans dominate. The pool starts at the first scan
        (forked, so with this process's compiled kernels) and stops with :meth:`close`.
    **options
        Further options of :class:`~rankedassign.tracking.GLMBFilter`
        (``prune_hypothesis``, ``theta_upper``, ``theta_lower``, ``prune_component``,
        ``merge_threshold``, ``merge_rule``, ``max_components``).

    Raises
    ------
    TypeError, ValueError
        As :class:`~rankedassign.tracking.GLMBFilter`; ``ValueError`` for ``gate_prob=None``,
        ``extraction="trajectory"`` or ``keep_histories``; ``workers`` not an int ``>= 1``.

    Notes
    -----
    A cluster's scan sees only its own measurements; the clutter term ``κ`` of a measurement
    and the scan constant ``−λ_c + m ln(λ_c c)`` cancel within each cluster's normalisation,
    so a scan of independent clusters is the scan of their product exactly. The split at step 3
    is where the clustered filter approximates the unclustered one: it drops the correlation
    between the parts of a cluster whose labels no longer share a measurement.

    References
    ----------
    .. [1] M. Beard, B.-T. Vo, B.-N. Vo, "A Solution for Large-Scale Multi-Object Tracking",
       IEEE Trans. Signal Process. 68:2754-2769, 2020.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking import Murty, make_model
    >>> from rankedassign.tracking.clustered import ClusteredGLMBFilter
    >>> f = ClusteredGLMBFilter(make_model("vo"), Murty(50))
    >>> for k in range(3):          # one target near birth location 2, no clutter
    ...     rec = f.step([[400.0 - 10 * k, -600.0 + 5 * k]], rng=k)
    >>> rec.labels.tolist()
    [[1, 2]]

    The target's cluster holds the births of its place; every birth elsewhere, which gates
    nothing, is a cluster of one label until its existence is pruned:

    >>> rec.n_clusters, int(rec.cluster_sizes.max())
    (10, 3)
    """

    #: The runners pass no ``grouping=`` (every cluster's components are truncated whole).
    takes_grouping = False

    def __init__(self, model: Model, association, *, gate_prob: float = 0.9999999,
                 h_upd: int = 1000, h_max: int = 1000, extraction: str | None = None,
                 retained_mass: bool = False, workers: int = 1, **options):
        check_type(model, "model", (Model, NonlinearModel),
                   "build one with make_model(preset) or Model(...)")
        self.workers = check_int(workers, "workers", minimum=1)
        self._executor = None
        if gate_prob is None:
            raise ValueError("ClusteredGLMBFilter needs a gate (gate_prob=None would put every "
                             "label in one cluster): use GLMBFilter without gating")
        if extraction == "trajectory" or options.get("keep_histories"):
            raise ValueError("ClusteredGLMBFilter keeps no whole association histories (a "
                             "merge and a split would have to carry them); use extraction="
                             "'map' or 'hysteresis'")
        options.pop("keep_histories", None)
        # the template every cluster copies: all the option checks happen here, once
        self._template = _Cluster(model, association, gate_prob=gate_prob, h_upd=h_upd,
                                  h_max=h_max, extraction=extraction,
                                  retained_mass=retained_mass, keep_histories=False, **options)
        self.model = model
        self.association = association
        self.h_max = self._template.h_max
        self.extraction = self._template.extraction
        self.retained_mass = self._template.retained_mass
        self.gate = self._template.gate
        self.reset()

    def reset(self) -> None:
        """Forget every track: no cluster; scan 0."""
        self.k = 0
        self.clusters: list[_Cluster] = []

    def _new_cluster(self) -> _Cluster:
        c = copy.copy(self._template)
        c.reset()
        c.k = self.k
        return c

    def set_prior(self, labels, means, covs, components=None, weights=None) -> None:
        """Start from a δ-GLMB prior (as :meth:`GLMBFilter.set_prior
        <rankedassign.tracking.GLMBFilter.set_prior>`), held as one cluster.

        The first scan splits it into the clusters its gates define.

        Parameters
        ----------
        labels, means, covs, components, weights
            As :meth:`GLMBFilter.set_prior <rankedassign.tracking.GLMBFilter.set_prior>`.

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking import Murty, make_model
        >>> from rankedassign.tracking.clustered import ClusteredGLMBFilter
        >>> f = ClusteredGLMBFilter(make_model("vo"), Murty(10))
        >>> f.set_prior([[0, 1], [0, 2]], np.zeros((2, 4)), np.tile(np.eye(4), (2, 1, 1)))
        >>> len(f.clusters), f.clusters[0].n_tracks
        (1, 2)
        """
        self.reset()
        c = self._new_cluster()
        c.set_prior(labels, means, covs, components, weights)
        self.clusters = [c] if c.n_tracks else []

    @property
    def n_clusters(self) -> int:
        """Clusters held."""
        return len(self.clusters)

    # ----------------------------------------------------------------------- the scan
    def step(self, z, rng=None) -> ClusteredScanRecord:
        """Run one scan: gate, regroup (split and merge), filter every cluster, combine.

        Parameters
        ----------
        z : array_like, shape (M, 2)
            Measurements of the scan.
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts; one draw from it and each
            cluster's smallest label key that cluster's stream.

        Returns
        -------
        ClusteredScanRecord

        Raises
        ------
        TypeError, ValueError
            On measurements as :meth:`GLMBFilter.step
            <rankedassign.tracking.GLMBFilter.step>`; ``ValueError`` before a cluster whose
            terms would take more than :data:`CLUSTER_WORK_BYTES` (every track gated to every
            measurement in a large scene), with the size.
        """
        tpl = self._template
        z = _check_measurements(z) if tpl._so is None else tpl._so.check_measurements(z)
        gen = spawning_generator(rng)
        key = int(gen.integers(0, _TWO63, dtype=np.uint64))
        t0 = perf_counter()
        M = z.shape[0]
        B = tpl._birth_r.size
        # 1. predicted entries of every cluster (as _predict computes them) and the births
        ms, Ps, offs, lab_of_entry = [], [], [np.zeros(1, np.int64)], []
        cl_label_keys, n_labels, n_comp = [], 0, 0
        cl_inv = []
        for c in self.clusters:
            if c._ukeys is None:
                ukeys, inv = np.unique(_label_keys(c.labels), return_inverse=True)
                inv = inv.reshape(-1)
                c._ukeys = ukeys
            else:  # the distinct keys the last scan recorded: each entry's is among them
                ukeys = c._ukeys
                inv = np.searchsorted(ukeys, _label_keys(c.labels))
            cl_label_keys.append(ukeys)
            cl_inv.append(inv)
            lab_of_entry.append(n_labels + inv)
            n_labels += ukeys.size
            m, P = _predicted(c, c.m, c.P)
            c._pred = (m, P)
            ms.append(m)
            Ps.append(P)
            offs.append(c.offsets[1:] + n_comp)
            n_comp += c.w.size
        n_birth, _ = _birth_components(tpl, np.arange(B))
        ms.append(tpl._birth_m)
        Ps.append(tpl._birth_P)
        offs.append(n_comp + np.cumsum(n_birth))
        lab_of_entry.append(n_labels + np.arange(B))
        L = n_labels + B
        m_all = np.ascontiguousarray(np.concatenate(ms))
        P_all = np.ascontiguousarray(np.concatenate(Ps))
        off_all = np.concatenate(offs).astype(np.int64)
        entry_label = np.concatenate(lab_of_entry).astype(np.int64)
        # 2. gate and group the labels
        if tpl._so is None:
            pairs = gate_pairs(m_all, P_all, tpl._R, z, off_all, self.gate)
        else:  # in the sensor's own coordinates (a bearing wraps)
            pairs = tpl._so.gate_pairs(m_all, P_all, z, off_all, self.gate)
        n_gated = int(np.unique(pairs.meas).size)
        groups = clusters(GatedPairs(entry_label[pairs.track], pairs.meas, L, M,
                                     pairs.n_candidates))
        g_of_label = groups.track_cluster
        cols_of = groups.groups()
        # 3. split: the parts of every cluster, by group
        parts: list[list] = [[] for _ in range(groups.n_clusters)]
        n_splits = 0
        start = 0
        for c, ukeys, inv in zip(self.clusters, cl_label_keys, cl_inv, strict=True):
            n = ukeys.size
            lab_g = g_of_label[start:start + n]
            if (lab_g == lab_g[0]).all():  # the common case: the cluster stays whole
                parts[int(lab_g[0])].append(c)
            else:
                g_e = lab_g[inv]
                gs = np.unique(lab_g)
                n_splits += 1
                for g in gs.tolist():
                    parts[g].append(_marginal(c, g_e == g))
            start += n
        births_of = [[] for _ in range(groups.n_clusters)]
        for b, g in enumerate(g_of_label[n_labels:].tolist()):
            births_of[g].append(b)
        # 4.-5. merge the parts of each group, add its births, run its scan
        t1 = perf_counter()
        timings = {"prediction": t1 - t0, "cost": 0.0, "association": 0.0, "update": 0.0}
        new_clusters, recs, scanned_sizes, tasks = [], [], [], []
        n_merges, dropped = 0, 0.0
        for g in range(groups.n_clusters):
            # the parts in increasing order of their smallest label: the product's table (and
            # so the rows of its problems) does not depend on the order of self.clusters
            ps = parts[g]
            if len(ps) > 1:
                ps = sorted(ps, key=lambda p: int(_label_keys(p.labels).min()))
            if not ps:
                c = self._new_cluster()
            else:
                c = ps[0]
                if len(ps) > 1:
                    n_merges += 1
                    for p in ps[1:]:
                        c, d = _product(c, p, self.h_max)
                        dropped = max(dropped, d)
            sel = np.array(births_of[g], dtype=np.int64)
            c._birth_sel = sel
            cols = cols_of[g][1]
            n_gauss = c.w.size + int(n_birth[sel].sum())
            need = n_gauss * cols.size * PAIR_BYTES
            if need > CLUSTER_WORK_BYTES:
                raise ValueError(
                    f"a cluster of {np.unique(_label_keys(c.labels)).size + sel.size} labels "
                    f"({n_gauss} Gaussian components) gates {cols.size} "
                    f"measurements: its scan would need {_size(need)} for its terms, above "
                    f"{_size(CLUSTER_WORK_BYTES)} (CLUSTER_WORK_BYTES); the gates join too "
                    "much of the scene into one cluster: narrow them (gate_prob) or split the "
                    "scene")
            labs = c._ukeys if c._ukeys is not None else np.unique(_label_keys(c.labels))
            first = int(labs[0]) if labs.size else None
            if sel.size:
                bkey = (self.k + 1) * (1 << 32) + int(sel[0]) + 1
                first = bkey if first is None else min(first, bkey)
            tasks.append((c, np.ascontiguousarray(z[cols]), [key, first]))
            scanned_sizes.append(int(labs.size + sel.size))
        # 5. the clusters' scans: each depends on its own state, measurements and stream only,
        # so any split of them over processes gives the same numbers
        for c, rec in self._run(tasks):
            for name in timings:
                timings[name] += rec.timings[name]
            recs.append(rec)
            if c.comp_tracks.size:  # a cluster without any track carries nothing
                # the record's track labels are the table's distinct labels, increasing
                c._ukeys = _label_keys(rec.track_labels)
                new_clusters.append(c)
        self.k += 1
        # the clusters in increasing order of their smallest label: a stable order
        firsts = [int(c._ukeys[0]) for c in new_clusters]
        order = np.argsort(firsts, kind="stable")
        self.clusters = [new_clusters[i] for i in order]
        return self._record(recs, scanned_sizes, M, n_gated, timings, n_merges, n_splits,
                            dropped)

    def _run(self, tasks: list) -> list:
        """``(cluster, record)`` of every task, in task order: here, or in ``workers``
        processes in contiguous chunks."""
        if self.workers == 1 or len(tasks) < 2:
            return _scan_clusters(tasks)
        if self._executor is None:
            # fork: the workers start with the compiled kernels of this process
            self._executor = ProcessPoolExecutor(self.workers,
                                                 mp_context=multiprocessing.get_context("fork"))
        n_chunks = min(len(tasks), 4 * self.workers)
        bounds = np.linspace(0, len(tasks), n_chunks + 1).round().astype(int)
        chunks = [tasks[a:b] for a, b in zip(bounds[:-1], bounds[1:], strict=True)]
        return [r for part in self._executor.map(_scan_clusters, chunks) for r in part]

    def close(self) -> None:
        """Stop the worker processes (``workers > 1``); the next scan starts new ones.

        Examples
        --------
        >>> from rankedassign.tracking import Murty, make_model
        >>> from rankedassign.tracking.clustered import ClusteredGLMBFilter
        >>> ClusteredGLMBFilter(make_model("vo"), Murty(5), workers=2).close()
        """
        if self._executor is not None:
            self._executor.shutdown()
            self._executor = None

    def _record(self, recs, scanned_sizes, M, n_gated, timings, n_merges, n_splits, dropped):
        def cat(name, shape):
            arrs = [getattr(r, name) for r in recs]
            return np.concatenate(arrs) if arrs else np.empty(shape)

        labels = cat("labels", (0, 2)).astype(np.int64).reshape(-1, 2)
        d = self._template._d
        states = cat("states", (0, d)).reshape(-1, d)
        ex = cat("existence", (0,))
        o = np.argsort(_label_keys(labels), kind="stable")
        tl = cat("track_labels", (0, 2)).astype(np.int64).reshape(-1, 2)
        tr = cat("track_existence", (0,))
        ot = np.argsort(_label_keys(tl), kind="stable")
        rm = np.array([r.retained_mass for r in recs])
        reached = np.isfinite(rm)
        if not self.retained_mass:
            retained, reason = math.nan, "not computed (retained_mass=False)"
        else:
            retained = float(np.prod(rm[reached]))
            sizes = np.array(scanned_sizes)
            reason = ("" if reached.all() else
                      f"{int((~reached).sum())} clusters beyond the oracle's DP left out "
                      f"(sizes {sorted(sizes[~reached].tolist())})")
        return ClusteredScanRecord(
            labels=labels[o], states=states[o], existence=ex[o], track_labels=tl[ot],
            track_existence=tr[ot], n_tracks=sum(r.n_tracks for r in recs), n_meas=M,
            n_meas_gated=n_gated, n_groups=sum(r.n_groups for r in recs),
            invocations=sum(r.invocations for r in recs), sweeps=sum(r.sweeps for r in recs),
            row_updates=sum(r.row_updates for r in recs),
            n_unique=sum(r.n_unique for r in recs), timings=timings,
            cardinality=_convolve_all([r.cardinality for r in recs]),
            n_components=sum(c.n_components for c in self.clusters),
            retained_mass=retained, retained_mass_reason=reason, trajectories=(),
            n_clusters=len(self.clusters),
            cluster_sizes=np.array([c._ukeys.size for c in self.clusters], dtype=np.int64),
            cluster_retained_mass=rm, cluster_scanned_sizes=np.array(scanned_sizes,
                                                                     dtype=np.int64),
            n_merges=n_merges, n_splits=n_splits, merge_dropped_mass=dropped,
        )

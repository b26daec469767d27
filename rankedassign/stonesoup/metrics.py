"""OSPA(2) as a Stone Soup metric generator (:func:`rankedassign.metrics.ospa2`)."""

from __future__ import annotations

import numbers

import numpy as np
from stonesoup.base import Property
from stonesoup.metricgenerator.base import MetricGenerator
from stonesoup.types.metric import SingleTimeMetric, TimeRangeMetric
from stonesoup.types.state import State, StateMutableSequence
from stonesoup.types.time import TimeRange

from ..metrics import ospa2

__all__ = ["OSPA2Metric"]


def _paths(objects, name: str) -> list[list]:
    """The states of every track or truth (a single ``State`` is a path of one state)."""
    out = []
    for obj in objects:
        if isinstance(obj, StateMutableSequence) and not isinstance(obj, State):
            # Stone Soup orders a path's states by timestamp: check them before it compares
            _check_timestamps([obj.states], name)
            try:
                out.append(list(obj.last_timestamp_generator()))
            except TypeError:
                kinds = sorted({type(s.timestamp).__name__ for s in obj.states})
                raise TypeError(_unordered(kinds)) from None
        elif isinstance(obj, State):
            out.append([obj])
        else:
            raise TypeError(f"OSPA2Metric: {name} must hold tracks or states, got "
                            f"{type(obj).__name__}")
    return out


def _check_mapping(mapping):
    """``mapping`` as a tuple of distinct non-negative ints, or None."""
    if mapping is None:
        return None
    if isinstance(mapping, (str, bytes)) or not hasattr(mapping, "__iter__"):
        raise TypeError(f"OSPA2Metric: mapping must be None or a sequence of state dimensions "
                        f"(ints), got {type(mapping).__name__} {mapping!r}")
    out = []
    for i in mapping:
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, numbers.Integral):
            raise TypeError(f"OSPA2Metric: mapping must hold state dimensions (ints), got "
                            f"{type(i).__name__} {i!r}")
        if i < 0:
            # -1 would count from the end of a state vector, which no mapping means
            raise ValueError(f"OSPA2Metric: mapping must hold non-negative state dimensions, "
                             f"got {i}")
        out.append(int(i))
    if not out:
        raise ValueError("OSPA2Metric: mapping is empty, so every distance would be 0; give "
                         "the dimensions to compare, e.g. (0, 2), or None for all")
    if len(set(out)) != len(out):
        raise ValueError(f"OSPA2Metric: mapping repeats a dimension: {tuple(out)}")
    return tuple(out)


def _unordered(kinds) -> str:
    return (f"OSPA2Metric: the states' timestamps cannot be ordered, they mix "
            f"{', '.join(kinds)}; give every state a datetime timestamp")


def _check_timestamps(paths, name: str) -> set:
    """Every state has a timestamp, and all are of one comparable kind (sorted into scans)."""
    kinds = set()
    for path in paths:
        for s in path:
            if s.timestamp is None:
                raise TypeError(f"OSPA2Metric: a state of {name} has no timestamp (None); "
                                "OSPA(2) orders the scans by the states' timestamps")
            kinds.add(type(s.timestamp))
    return kinds


def _array(paths, times: dict, mapping, name: str) -> np.ndarray:
    """``(n_scans, n_paths, d)`` with NaN where a path has no state at a scan."""
    sizes = {np.asarray(s.state_vector).size for p in paths for s in p}
    if mapping is not None and sizes and max(mapping) >= min(sizes):
        raise ValueError(f"OSPA2Metric: mapping {mapping} names dimension {max(mapping)}, and "
                         f"the {name} have states of {min(sizes)} dimensions")
    dims = {len(mapping) if mapping is not None else size for size in sizes}
    if len(dims) > 1:
        raise ValueError(f"OSPA2Metric: the {name} have states of different dimensions "
                         f"{sorted(dims)}; set mapping to the dimensions to compare")
    d = dims.pop() if dims else 1
    out = np.full((len(times), len(paths), d), np.nan)
    for n, path in enumerate(paths):
        for state in path:
            x = np.asarray(state.state_vector, dtype=np.float64).reshape(-1)
            out[times[state.timestamp], n] = x if mapping is None else x[list(mapping)]
    return out


class OSPA2Metric(MetricGenerator):
    """OSPA(2) between a set of tracks and a set of truths, at every timestamp.

    The OSPA(2) metric of Beard, Vo & Vo (2020), a distance between sets of *tracks* (of
    trajectories) rather than of points, over a sliding window of scans; its values are those
    of :func:`rankedassign.metrics.ospa2` on the same tracks and truths. It works with Stone
    Soup's ``MultiManager`` and ``MetricPlotter`` beside ``OSPAMetric``.

    Parameters
    ----------
    c : float
        Cut-off distance, ``> 0``.
    p : float
        Order, ``>= 1``.
    window : int
        Number of scans ``N >= 1`` of the window ending at each timestamp (1: OSPA of every
        scan's states, with the track distances as base distances).
    base : {"euclidean", "lp"}, optional
        Per-scan base distance (:func:`~rankedassign.metrics.ospa2`): the Euclidean distance
        cut at ``c`` (default, spec §7), or Beard's ``min(c^p, sum |x - y|^p)``.
    weight_power : float, optional
        Power ``r`` of the window weights ``w_t = (t - k + N)^r`` (0, default: uniform).
    mapping : sequence of int, optional
        State dimensions to compare, e.g. ``(0, 2)`` for the positions of ``[x, vx, y, vy]``:
        distinct non-negative ints, at least one (checked at construction, and against the
        states' dimension when the metric is computed); None (default) compares every
        dimension.
    generator_name : str, optional
        Name of the generator in a ``MultiManager`` (default ``"ospa2_generator"``).
    tracks_key : str, optional
        Key of the tracks in the manager's data (default ``"tracks"``).
    truths_key : str, optional
        Key of the truths (default ``"groundtruth_paths"``).

    Notes
    -----
    The scans are the sorted union of the timestamps of every state of both sets; a track
    or truth exists at the scans where it has a state (its last state of each timestamp), and
    is NaN elsewhere, which is what :func:`~rankedassign.metrics.ospa2` expects. Spec §7,
    eqs. (7.1)–(7.3).

    References
    ----------
    .. [1] M. Beard, B.-T. Vo, B.-N. Vo, "A Solution for Large-Scale Multi-Object Tracking",
       IEEE Trans. Signal Process. 68, 2020 (arXiv:1804.06622).
    .. [2] D. Schuhmacher, B.-T. Vo, B.-N. Vo, "A Consistent Metric for Performance Evaluation
       of Multi-Object Filters", IEEE Trans. Signal Process. 56(8), 2008.

    Examples
    --------
    One truth and one track 3 m off that starts a scan late, as in
    :func:`rankedassign.metrics.ospa2`:

    >>> import datetime
    >>> from stonesoup.metricgenerator.manager import MultiManager
    >>> from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState
    >>> from stonesoup.types.state import State
    >>> from stonesoup.types.track import Track
    >>> from rankedassign.stonesoup import OSPA2Metric
    >>> t = [datetime.datetime(2025, 1, 1, 0, 0, k) for k in range(3)]
    >>> truth = GroundTruthPath([GroundTruthState([[x], [0.0]], timestamp=t[x]) for x in range(3)])
    >>> track = Track([State([[x], [3.0]], timestamp=t[x]) for x in (1, 2)])
    >>> gen = OSPA2Metric(c=10.0, p=1, window=2)
    >>> manager = MultiManager([gen])
    >>> manager.add_data({"groundtruth_paths": {truth}, "tracks": {track}})
    >>> metric = gen.compute_metric(manager)
    >>> [round(float(m.value), 6) for m in metric.value]
    [10.0, 6.5, 3.0]
    """

    c: float = Property(doc="Cut-off distance, > 0.")
    p: float = Property(doc="Order, >= 1.")
    window: int = Property(doc="Scans of the window ending at each timestamp, >= 1.")
    base: str = Property(default="euclidean", doc='Base distance: "euclidean" or "lp".')
    weight_power: float = Property(default=0.0, doc="Power of the window weights (0: uniform).")
    mapping: tuple = Property(default=None, doc="State dimensions to compare (None: all).")
    generator_name: str = Property(default="ospa2_generator",
                                   doc="Unique identifier of the generator in a MultiManager.")
    tracks_key: str = Property(default="tracks", doc="Key of the tracks in the manager.")
    truths_key: str = Property(default="groundtruth_paths",
                               doc="Key of the truths in the manager.")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.mapping = _check_mapping(self.mapping)

    def compute_metric(self, manager, **kwargs):
        """OSPA(2) of the manager's tracks against its truths.

        Parameters
        ----------
        manager : stonesoup.metricgenerator.manager.MultiManager
            Holds the tracks under :attr:`tracks_key` and the truths under
            :attr:`truths_key`.
        **kwargs
            Unused (Stone Soup's signature).

        Returns
        -------
        stonesoup.types.metric.TimeRangeMetric
            Titled ``"OSPA(2) distances"``; its ``value`` is a list of ``SingleTimeMetric``,
            one per timestamp in increasing order, whose ``value`` is the OSPA(2) distance.

        Raises
        ------
        TypeError
            If the manager's data are not tracks or states, or a state has no timestamp or
            the timestamps cannot be ordered (datetimes mixed with numbers).
        ValueError
            If neither set has a state, if states differ in dimension (without
            ``mapping``), if ``mapping`` names a dimension the states do not have, or on an
            invalid ``c``, ``p``, ``window`` or ``base``.
        """
        tracks = _paths(self._get_data(manager, self.tracks_key), "the tracks")
        truths = _paths(self._get_data(manager, self.truths_key), "the truths")
        kinds = _check_timestamps(tracks, "the tracks") | _check_timestamps(truths, "the truths")
        try:
            stamps = sorted({s.timestamp for path in tracks + truths for s in path})
        except TypeError:
            raise TypeError(_unordered(sorted(k.__name__ for k in kinds))) from None
        if not stamps:
            raise ValueError("OSPA2Metric: neither the tracks nor the truths have a state")
        times = {t: k for k, t in enumerate(stamps)}
        X = _array(truths, times, self.mapping, "truths")
        Y = _array(tracks, times, self.mapping, "tracks")
        value = ospa2(X, Y, c=self.c, p=self.p, window=self.window,
                      weight_power=self.weight_power, base=self.base).value
        singles = [SingleTimeMetric(title="OSPA(2) distance", value=float(v), timestamp=t,
                                    generator=self) for t, v in zip(stamps, value, strict=True)]
        return TimeRangeMetric(title="OSPA(2) distances", value=singles,
                               time_range=TimeRange(stamps[0], stamps[-1]), generator=self)

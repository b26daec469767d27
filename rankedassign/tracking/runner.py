"""Run a filter over a sequence of scans: the one scan loop of the library.

:func:`run_filter` takes a filter and the measurements of every scan (simulated, or read from a
file with :func:`~rankedassign.tracking.io.read_measurements`) and does what every run needs:
one child random stream per scan, the labelled estimates and existence probabilities of every
scan, the per-scan counters and timings as arrays, the NaN-padded track array of the estimates
and, given the truth, OSPA and OSPA(2). The scenario runners
(:func:`~rankedassign.tracking.run.run_scenario`,
:func:`~rankedassign.tracking.run.run_multisensor_scenario`) are this loop on
simulated measurements.
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from ..engine.rng import spawning_generator
from ..metrics import OSPA2Result, ospa2, tracks_to_array
from .scenario import COUNTER_KEYS, Truth

__all__ = ["FilterRun", "OSPA_C", "OSPA_P", "OSPA2_WINDOW", "TIMING_KEYS", "run_filter"]

#: Phases every :class:`FilterRun` has timings of (further phases a filter reports, such as the
#: multi-sensor filter's ``"birth"``, follow in order of first appearance).
TIMING_KEYS = ("prediction", "cost", "association", "update")
#: OSPA cut-off ``c`` (m), order ``p`` and OSPA(2) window of :func:`run_filter`: the paper's
#: tracking study (spec §7).
OSPA_C, OSPA_P, OSPA2_WINDOW = 200.0, 1.0, 5


@dataclass(frozen=True, eq=False)
class FilterRun:
    """Result of :func:`run_filter`: the fields of
    :class:`~rankedassign.tracking.scenario.ScenarioRun` but ``scenario``, and the metrics.

    Attributes
    ----------
    association : str or None
        ``repr`` of the filter's ``association`` (None for a filter without one).
    extraction : str or None
        The filter's ``extraction`` (the state extraction it used), None if it has none.
    truth : ndarray, shape (n_scans, n_targets, 2), or None
        True positions, NaN where a target does not exist; None when no truth was given.
    estimates : ndarray, shape (n_scans, n_est_tracks, 2)
        Estimated positions, one column per reported label (order of first report), NaN where
        a label is not reported.
    estimate_labels : list of tuple
        Labels ``(birth scan, birth index)`` of the columns of ``estimates``, tuples of ints.
    labelled_estimates : list of dict
        Per scan, ``{label: state (4,)}`` of the reported tracks.
    existence : list of dict
        Per scan, ``{label: r}`` of every track held after the update.
    invocations, sweeps, row_updates, n_unique, n_tracks, n_estimated, n_meas, n_meas_gated, \
n_groups : ndarray of int64, shape (n_scans,)
        The per-scan counters of :class:`~rankedassign.tracking.single.lmb.ScanRecord`, and
        ``n_estimated``, the tracks reported per scan.
    n_births : ndarray of int64, shape (n_scans,), or None
        Birth tracks appended by each scan's prediction, for a filter that reports them (its
        attribute ``n_births``, e.g. the multi-sensor filter); None otherwise.
    timings : dict of ndarray, shape (n_scans,)
        Seconds per scan of every phase the filter times (:data:`TIMING_KEYS` first, 0 where
        a scan did not report a phase).
    ospa, ospa2 : OSPA2Result or None
        With a truth: per-scan OSPA and OSPA(2) of the position estimates (``c = 200`` m,
        ``p = 1``, OSPA(2) window 5: :data:`OSPA_C`, :data:`OSPA_P`, :data:`OSPA2_WINDOW`);
        for other settings call :func:`~rankedassign.metrics.ospa2` on ``truth`` and
        ``estimates``. None without a truth.
    """

    association: str | None
    extraction: str | None
    truth: np.ndarray | None
    estimates: np.ndarray
    estimate_labels: list
    labelled_estimates: list
    existence: list
    invocations: np.ndarray
    sweeps: np.ndarray
    row_updates: np.ndarray
    n_unique: np.ndarray
    n_tracks: np.ndarray
    n_estimated: np.ndarray
    n_meas: np.ndarray
    n_meas_gated: np.ndarray
    n_groups: np.ndarray
    n_births: np.ndarray | None
    timings: dict
    ospa: OSPA2Result | None
    ospa2: OSPA2Result | None

    @property
    def n_scans(self) -> int:
        """Number of scans."""
        return int(self.estimates.shape[0])


def _check_filter(filt) -> None:
    """Refuse what has no ``step(z, rng)`` and ``reset()``."""
    missing = [name for name in ("step", "reset") if not callable(getattr(filt, name, None))]
    if missing:
        raise TypeError(
            "run_filter needs a filter with methods step(z, rng) and reset(), such as LMBFilter "
            f"or MultiSensorLMBFilter; got {type(filt).__name__} without "
            f"{' and '.join(m + '()' for m in missing)}"
        )


def _check_scans(scans) -> list:
    """``scans`` as a non-empty list, one entry per scan."""
    if isinstance(scans, (str, bytes, Mapping)) or not isinstance(scans, Iterable):
        raise TypeError(
            "scans must be a sequence with one entry per scan (an (M, 2) array, or a tuple of "
            f"one array per sensor), got {type(scans).__name__}"
        )
    if isinstance(scans, np.ndarray) and scans.ndim < 3:
        raise ValueError(
            "scans must be a sequence with one entry per scan (an (M, 2) array, or a tuple of "
            f"one array per sensor), got one array of shape {scans.shape}; a single scan is "
            "[z]"
        )
    scans = list(scans)
    if not scans:
        raise ValueError("scans is empty: run_filter needs at least one scan")
    return scans


def _check_truth(truth, n_scans: int) -> np.ndarray | None:
    """The true positions (n_scans, n_targets, 2) of a Truth or an array, or None."""
    if truth is None:
        return None
    if isinstance(truth, Truth):
        truth = truth.positions
    try:
        a = np.asarray(truth)
    except ValueError:  # numpy: "inhomogeneous shape"
        raise ValueError("truth must be an (n_scans, n_targets, 2) array of positions (NaN "
                         "where a target does not exist), got a ragged sequence") from None
    if a.dtype.kind not in "iuf":
        raise TypeError(f"truth must hold real numbers (NaN where a target does not exist), "
                        f"got dtype {a.dtype}")
    if a.ndim != 3 or a.shape[2] != 2 or a.shape[0] != n_scans:
        raise ValueError(
            f"truth must have shape (n_scans, n_targets, 2) = ({n_scans}, n_targets, 2), one "
            f"row of positions per scan, got shape {a.shape}"
        )
    return np.array(a, dtype=np.float64)


def _check_record(rec, filt, k: int) -> None:
    """Refuse what ``filt.step`` returned if it is not a scan record run_filter can read."""
    who = f"run_filter: {type(filt).__name__}.step returned"
    fields = ("labels", "states", "track_labels", "track_existence", "timings", *COUNTER_KEYS)
    missing = [name for name in fields if not hasattr(rec, name)]
    if missing:
        raise TypeError(
            f"{who} {type(rec).__name__} at scan {k}, without {', '.join(missing)}; step must "
            "return a record with the fields of ScanRecord (labels (n, 2), states (n, 4), "
            f"track_labels (L, 2), track_existence (L,), timings and {', '.join(COUNTER_KEYS)})"
        )

    def array(name, kinds, shape):
        try:
            a = np.asarray(getattr(rec, name))
        except ValueError:  # numpy: "inhomogeneous shape"
            raise ValueError(f"{who} a ragged {name} at scan {k}") from None
        if a.dtype.kind not in kinds:
            what = "ints" if kinds == "iu" else "real numbers"
            raise TypeError(f"{who} {name} of dtype {a.dtype} at scan {k}, expected {what}")
        if a.ndim != len(shape) or any(w is not None and d != w
                                       for d, w in zip(a.shape, shape, strict=True)):
            want = ", ".join(str(w) if w is not None else "n" if i == 0 else "d"
                             for i, w in enumerate(shape))
            want = f"({want},)" if len(shape) == 1 else f"({want})"
            raise ValueError(f"{who} {name} of shape {a.shape} at scan {k}, expected {want}")
        return a

    n = array("labels", "iu", (None, 2)).shape[0]
    array("states", "iuf", (n, None))
    if np.asarray(rec.states).shape[1] < 3:
        raise ValueError(f"{who} states of shape {np.asarray(rec.states).shape} at scan {k}, "
                         "expected (n, 4): the positions are columns 0 and 2")
    L = array("track_labels", "iu", (None, 2)).shape[0]
    array("track_existence", "iuf", (L,))
    for name in COUNTER_KEYS:
        value = getattr(rec, name)
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
            raise TypeError(f"{who} {name} = {value!r} at scan {k}, expected an int")
    timings = rec.timings
    if not isinstance(timings, Mapping) or not all(
            isinstance(key, str) and isinstance(v, numbers.Real) and not isinstance(v, bool)
            for key, v in timings.items()):
        raise TypeError(f"{who} timings = {timings!r} at scan {k}, expected a dict of phase "
                        "names to seconds")


def _label_key(label) -> tuple:
    """A label row as a tuple of Python ints (a scalar label as a 1-tuple)."""
    return tuple(label) if isinstance(label, list) else (label,)


def run_filter(filter, scans, *, rng=None, truth=None) -> FilterRun:
    """Run a filter over a sequence of scans and collect its estimates, counters and timings.

    Parameters
    ----------
    filter : LMBFilter, MultiSensorLMBFilter or any object with the same interface
        The filter to run. It is :meth:`reset <rankedassign.tracking.single.lmb.LMBFilter.reset>`
        first, so that a run depends only on ``scans`` and ``rng``. Any object works that has
        ``reset()`` and ``step(z, rng)``, where ``step`` returns a record with the fields of
        :class:`~rankedassign.tracking.single.lmb.ScanRecord` (``labels`` (n, 2), ``states`` (n, 4),
        ``track_labels``, ``track_existence``, ``timings`` and the counters
        :data:`~rankedassign.tracking.scenario.COUNTER_KEYS`); ``association``,
        ``extraction`` and ``n_births`` are read when it has them. A δ-GLMB filter with this
        interface runs unchanged.
    scans : sequence
        One entry per scan, passed as it is to ``filter.step``: for the single-sensor filter an
        ``(M, 2)`` array of positions (``[]`` for a scan without measurements), for the
        multi-sensor filter a tuple of one such array per sensor, in the model's sensor order.
        :func:`~rankedassign.tracking.io.read_measurements` reads them from a CSV file.
    rng : optional
        Anything :func:`numpy.random.default_rng` accepts. One child stream per scan is
        spawned from it (:meth:`numpy.random.Generator.spawn`), and scan ``k`` runs on child
        ``k``, whatever the association. Spawning advances a Generator's seed sequence, so a
        Generator passed twice gives two different runs; pass a seed (or a fresh Generator) to
        repeat one. A :class:`numpy.random.RandomState` is replaced by the
        Generator seeded with one draw from it (:func:`rankedassign.engine.rng.spawning_generator`).
        :func:`~rankedassign.tracking.run.run_scenario` runs its filter with the second child
        of its own ``rng`` (the first draws the measurements), so
        ``np.random.default_rng(seed).spawn(2)[1]`` here reproduces ``run_scenario(...,
        rng=seed)`` on its scenario's measurements.
    truth : Truth or array_like, shape (n_scans, n_targets, 2), optional
        True positions, NaN where a target does not exist (a
        :class:`~rankedassign.tracking.scenario.Truth` gives its ``positions``). With it, the
        result holds OSPA and OSPA(2) per scan.

    Returns
    -------
    FilterRun
        Estimates (labelled, and as a NaN-padded track array of positions), existence,
        counters and timings per scan; OSPA and OSPA(2) when ``truth`` is given.

    Raises
    ------
    TypeError
        If ``filter`` has no ``step`` or ``reset`` method, ``scans`` is not a sequence,
        ``truth`` does not hold real numbers, ``rng`` is of a kind numpy cannot seed from, or
        ``filter.step`` returns something that is not a scan record (a missing field, labels
        that are not ints, counters that are not ints; the message names the filter's class).
    ValueError
        If ``scans`` is empty or a single array of fewer than three dimensions, ``truth``
        does not have one row per scan of 2-D positions, or a field of ``filter.step``'s
        record has the wrong shape. Errors of ``filter.step`` (a malformed
        scan, a wrong number of sensors) propagate unchanged, with a note naming the scan.

    Notes
    -----
    The loop, for scan ``k = 0, 1, ...``: ``record = filter.step(scans[k], rng=child[k])``;
    ``labelled_estimates[k] = {label: state}`` of the reported tracks, ``existence[k] =
    {label: r}`` of every track held, and the counters and timings of the record. The track
    array keeps the position components ``(p_x, p_y)`` of the states
    (:func:`~rankedassign.metrics.tracks_to_array` with ``dims=(0, 2)``).

    References
    ----------
    .. [1] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.
    .. [2] M. Beard, B.-T. Vo, B.-N. Vo, "A Solution for Large-Scale Multi-Object Tracking",
       IEEE Trans. Signal Process. 68, 2020 (OSPA(2)).

    Examples
    --------
    The same run as :func:`~rankedassign.tracking.run.run_scenario`, from the measurements:

    >>> import numpy as np
    >>> from rankedassign.tracking import (Exact, LMBFilter, make_model, make_scenario,
    ...                                    run_filter, run_scenario)
    >>> meas_rng, filter_rng = np.random.default_rng(1).spawn(2)
    >>> sc = make_scenario("vo", rng=meas_rng, n_scans=4)
    >>> run = run_filter(LMBFilter(make_model("vo"), Exact()), [s.z for s in sc.scans],
    ...                  rng=filter_rng, truth=sc.truth)
    >>> run.extraction, run.estimates.shape[0], run.ospa2.value.shape
    ('map', 4, (4,))
    >>> ref = run_scenario("vo", Exact(), rng=1, n_scans=4)
    >>> bool(np.array_equal(run.estimates, ref.estimates, equal_nan=True))
    True
    """
    _check_filter(filter)
    scans = _check_scans(scans)
    K = len(scans)
    true_pos = _check_truth(truth, K)
    scan_rngs = spawning_generator(rng).spawn(K)
    filter.reset()
    reports_births = hasattr(filter, "n_births")
    labelled, existence, counts, births, times = [], [], [], [], []
    for k, z in enumerate(scans):
        try:
            rec = filter.step(z, rng=scan_rngs[k])
        except (TypeError, ValueError) as exc:
            if hasattr(exc, "add_note"):  # Python >= 3.11
                exc.add_note(f"in scan {k} (scans[{k}]) of the {K} given to run_filter")
            raise
        _check_record(rec, filter, k)
        # labels as tuples of Python ints, existence as Python floats
        labelled.append(dict(zip(map(_label_key, np.asarray(rec.labels).tolist()), rec.states,
                                 strict=True)))
        existence.append(dict(zip(map(_label_key, np.asarray(rec.track_labels).tolist()),
                                  np.asarray(rec.track_existence).tolist(), strict=True)))
        counts.append([getattr(rec, name) for name in COUNTER_KEYS] + [len(rec.labels)])
        if reports_births:
            births.append(filter.n_births)
        times.append(rec.timings)
    counts = np.array(counts, dtype=np.int64).reshape(K, len(COUNTER_KEYS) + 1)
    counters = {name: counts[:, i].copy() for i, name in enumerate(COUNTER_KEYS)}
    counters["n_estimated"] = counts[:, -1].copy()
    keys = list(TIMING_KEYS)
    for t in times:
        keys += [name for name in t if name not in keys]
    timings = {name: np.array([t.get(name, 0.0) for t in times], dtype=np.float64)
               for name in keys}
    # the position components the model names (a non-linear model's sensor); (0, 2) otherwise
    dims = tuple(getattr(getattr(filter, "model", None), "position_indices", (0, 2)))
    est, labels = tracks_to_array(labelled, dims=dims, return_labels=True)
    if est.shape[2] == 0:  # nothing was ever reported
        est = np.full((K, 0, 2), np.nan)
    metrics = {"ospa": None, "ospa2": None}
    if true_pos is not None:
        for name, window in (("ospa", 1), ("ospa2", OSPA2_WINDOW)):
            metrics[name] = ospa2(true_pos, est, c=OSPA_C, p=OSPA_P, window=window)
    assoc = getattr(filter, "association", None)
    extraction = getattr(filter, "extraction", None)
    return FilterRun(
        association=None if assoc is None else repr(assoc),
        extraction=extraction if isinstance(extraction, str) else None,
        truth=true_pos,
        estimates=est,
        estimate_labels=labels,
        labelled_estimates=labelled,
        existence=existence,
        n_births=np.array(births, dtype=np.int64) if reports_births else None,
        timings=timings,
        **counters,
        **metrics,
    )

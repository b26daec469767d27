"""What a filter is: the protocol every filter of the library follows, written down.

A filter holds its posterior between scans. :func:`~rankedassign.tracking.run_filter` and the
scenario runners need nothing else from it than :class:`Filter`: ``reset()`` forgets every
track, ``step(scan, rng)`` runs one scan and returns a record with the fields of
:class:`ScanRecordFields`. :class:`~rankedassign.tracking.LMBFilter`,
:class:`~rankedassign.tracking.GLMBFilter`,
:class:`~rankedassign.tracking.MultiSensorLMBFilter` and
:class:`~rankedassign.tracking.MultiSensorGLMBFilter` follow it; a filter of one's own that
does runs in :func:`~rankedassign.tracking.run_filter` unchanged, and in the scenario runners
when passed as an object or a class (:mod:`rankedassign.tracking.filters`).
"""

from __future__ import annotations

from typing import Any, NamedTuple, Protocol, runtime_checkable

import numpy as np

__all__ = ["Filter", "ScanRecordFields", "record_base"]


@runtime_checkable
class ScanRecordFields(Protocol):
    """The fields of the record a filter's ``step`` returns (what the runners read).

    Attributes
    ----------
    labels : ndarray of int64, shape (n, 2)
        Labels of the reported tracks.
    states : ndarray, shape (n, 4)
        Their state estimates.
    track_labels : ndarray of int64, shape (L, 2)
        Every label held, with ``track_existence`` of shape ``(L,)``.
    track_existence : ndarray, shape (L,)
    n_tracks, n_meas, n_meas_gated, n_groups, invocations, sweeps, row_updates, n_unique : int
        The counters (:data:`~rankedassign.tracking.scenario.COUNTER_KEYS`).
    timings : dict
        Seconds per phase (``prediction``, ``cost``, ``association``, ``update``, ...).

    Parameters
    ----------
    *args, **kwargs : object
        A protocol is not instantiated; the filters' own records follow it
        (:class:`~rankedassign.tracking.ScanRecord`,
        :class:`~rankedassign.tracking.GLMBScanRecord`).
    """

    labels: np.ndarray
    states: np.ndarray
    track_labels: np.ndarray
    track_existence: np.ndarray
    n_tracks: int
    n_meas: int
    n_meas_gated: int
    n_groups: int
    invocations: int
    sweeps: int
    row_updates: int
    n_unique: int
    timings: dict


def record_base(name: str, **extra: type) -> type:
    """The named tuple a filter's record class derives from: the protocol's fields, then its own.

    The fields are those of :class:`ScanRecordFields` in their order, with ``existence`` (the
    reported tracks' existence probabilities, which every filter of the library reports)
    after ``states``, then ``extra`` in the order given. A record class derives from it, adds
    its docstring and ``__slots__ = ()``, and so declares the protocol's fields once.

    Parameters
    ----------
    name : str
        The record's class name.
    **extra : type
        The record's own fields after the protocol's, with their types.

    Returns
    -------
    type
        A named-tuple class (made by ``typing.NamedTuple``).

    Examples
    --------
    >>> import numpy as np
    >>> class Record(record_base("Record", cardinality=np.ndarray)):
    ...     'One scan.'
    ...     __slots__ = ()
    >>> Record._fields[:4], Record._fields[-2:]
    (('labels', 'states', 'existence', 'track_labels'), ('timings', 'cardinality'))
    """
    fields = list(ScanRecordFields.__annotations__.items())
    fields.insert(fields.index(("states", "np.ndarray")) + 1, ("existence", "np.ndarray"))
    return NamedTuple(name, [*fields, *extra.items()])


@runtime_checkable
class Filter(Protocol):
    """A multi-object filter: ``reset()`` and ``step(scan, rng) -> record``.

    ``scan`` is one scan's measurements (an ``(M, 2)`` array for one sensor, one such array
    per sensor for several); ``rng`` anything :func:`numpy.random.default_rng` accepts. The
    record has the fields of :class:`ScanRecordFields`. Optional attributes the runners read
    when present: ``association`` (its ``repr`` is recorded), ``extraction`` and ``n_births``.

    Parameters
    ----------
    *args, **kwargs : object
        A protocol is not instantiated; ``isinstance(obj, Filter)`` checks the methods.

    Examples
    --------
    >>> from rankedassign.tracking import Exact, GLMBFilter, LMBFilter, make_model
    >>> from rankedassign.tracking.protocol import Filter
    >>> isinstance(LMBFilter(make_model("vo"), Exact()), Filter)
    True
    >>> isinstance(GLMBFilter(make_model("vo"), Exact()), Filter), isinstance(3, Filter)
    (True, False)
    """

    def reset(self) -> None:
        """Forget every track; the next ``step`` is the first scan."""

    def step(self, scan: Any, rng: Any = None) -> ScanRecordFields:
        """Run one scan and report it.

        Parameters
        ----------
        scan : array_like or sequence of array_like
            The scan's measurements (one array per sensor for several sensors).
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts.

        Returns
        -------
        ScanRecordFields
        """

"""Kernel records that extend others, declared once.

A kind's herded or tempered kernel reads one flat record: the Gibbs record's fields followed by
the draw's own (numba's parallel loop takes no nested tuple, and the Gibbs kernel's phases then
read it as they read the Gibbs record). :func:`record` builds the base of such a class from
its parts, so that no field list is written twice; :class:`HerdedDraw` holds the fields that
every kind's herded data record adds.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["HerdedDraw", "record"]


class HerdedDraw(NamedTuple):
    """The fields every kind's herded data record ends with (after its Gibbs fields and any
    of its own), read by the engine's key table (:func:`rankedassign.engine._kernels.herd_lookup`,
    :func:`~rankedassign.engine._kernels.herd_pick`, ``key_table_done``).

    Attributes
    ----------
    key_mode : int
        What a key is: ``KEY_CODES`` of :mod:`rankedassign.engine.herding` (0 full, 1 shared).
    init_mode : int
        A new key's initial weights: ``INIT_CODES`` (0 conditional, 1 zero, 2 uniform).
    capacity : int
        Keys a chain's table may hold.
    chain_length : int
        Observations per chain (sizes the per-sweep tallies of speculated chains).
    tally : ndarray, shape (2,), int64
        ``[keys created, fall-back draws]`` over the run, updated in place.
    """

    key_mode: int
    init_mode: int
    capacity: int
    chain_length: int
    tally: np.ndarray


def record(*parts):
    """The named-tuple base of a record whose fields are those of ``parts``, in order.

    The record itself is a class statement on this base, which gives it its name and
    docstring (numba compiles a subclass of a named tuple as it compiles the named tuple)::

        class MultiSensorHerdedData(record(MultiSensorData, {"gate": np.ndarray}, HerdedDraw)):
            '''The docstring, its Attributes naming every field.'''

    Parameters
    ----------
    *parts : NamedTuple class or dict
        Named-tuple classes (their fields, with their annotations) or ``{field: type}`` dicts.

    Returns
    -------
    type
        A ``typing.NamedTuple`` class with the fields of every part.

    Raises
    ------
    ValueError
        If two parts name the same field.

    Examples
    --------
    >>> from typing import NamedTuple
    >>> class Gibbs(NamedTuple):
    ...     W: float
    >>> class Tempered(record(Gibbs, {"beta": float})):
    ...     '''Gibbs inputs and an inverse temperature.'''
    >>> Tempered._fields, Tempered(W=1.0, beta=0.5)
    (('W', 'beta'), Tempered(W=1.0, beta=0.5))
    """
    fields = []
    for part in parts:
        if isinstance(part, dict):
            fields.extend(part.items())
            continue
        types = {}
        for klass in reversed(part.__mro__):
            types.update(klass.__dict__.get("__annotations__", {}))
        fields.extend((f, types.get(f, object)) for f in part._fields)
    names = [f for f, _ in fields]
    dup = sorted({f for f in names if names.count(f) > 1})
    if dup:
        raise ValueError(f"a record's parts name these fields twice: {', '.join(dup)}")
    return NamedTuple("Record", fields)

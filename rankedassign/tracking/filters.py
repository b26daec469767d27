"""The one table of the library's filters, and how the runners build the filter they run.

:data:`FILTERS` names every filter once, with its single- and multi-sensor class. The scenario
runners (:func:`~rankedassign.tracking.run_scenario`,
:func:`~rankedassign.tracking.run_multisensor_scenario`) take ``filter=`` as a name of the
table (the strings ``"lmb"`` and ``"glmb"`` of earlier releases), a filter class (of the table
or one's own, called as ``cls(model, association, **options)``) or a filter object that
follows :class:`~rankedassign.tracking.protocol.Filter` (run as it is). Adding a filter to the
library: its module, one row here, its export in :mod:`rankedassign.tracking`.
"""

from __future__ import annotations

from typing import NamedTuple

from .multisensor.glmb import MultiSensorGLMBFilter
from .multisensor.lmb import MultiSensorLMBFilter
from .protocol import Filter
from .single.glmb import GLMBFilter
from .single.lmb import LMBFilter

__all__ = ["FILTERS", "FilterEntry", "make_filter"]


class FilterEntry(NamedTuple):
    """One filter of the library.

    Attributes
    ----------
    single, multi : type
        Its class for one sensor and for several.
    grouping : bool
        It solves independent groups of tracks separately (takes ``grouping=``); the δ-GLMB
        filters truncate every component's problem whole.
    """

    single: type
    multi: type
    grouping: bool


#: Every filter of the library, by the name the runners and studies give it.
FILTERS: dict[str, FilterEntry] = {
    "lmb": FilterEntry(LMBFilter, MultiSensorLMBFilter, grouping=True),
    "glmb": FilterEntry(GLMBFilter, MultiSensorGLMBFilter, grouping=False),
}


def _entry(filter) -> FilterEntry | None:
    if isinstance(filter, str):
        entry = FILTERS.get(filter)
        if entry is None:
            raise ValueError(f"unknown filter {filter!r}; expected one of {tuple(FILTERS)}, a "
                             "filter class or a filter object")
        return entry
    for entry in FILTERS.values():
        if filter in (entry.single, entry.multi):
            return entry
    return None


def takes_grouping(filter) -> bool:
    """Whether the filter ``filter`` names (a name, class or object) takes ``grouping=``.

    Parameters
    ----------
    filter : str, type or Filter

    Returns
    -------
    bool
        True for the LMB filters; for a class or object of one's own, its class attribute
        ``takes_grouping`` (True when it has none).

    Examples
    --------
    >>> takes_grouping("glmb"), takes_grouping(LMBFilter)
    (False, True)
    """
    entry = _entry(filter if isinstance(filter, (str, type)) else type(filter))
    if entry is None:
        return bool(getattr(filter, "takes_grouping", True))
    return entry.grouping


def make_filter(filter, model, association, *, multi: bool, **options):
    """The filter a runner runs: ``filter`` built on ``model`` with ``association``.

    Parameters
    ----------
    filter : str, type or Filter
        A name of :data:`FILTERS`, a filter class (the table's classes stand for their row:
        :class:`~rankedassign.tracking.GLMBFilter` on a multi-sensor scenario builds
        :class:`~rankedassign.tracking.MultiSensorGLMBFilter`) or a filter object (returned as
        it is; then ``association`` must be None and ``options`` empty).
    model : Model or MultiSensorModel
        The scenario's model.
    association : object or None
        The filter's association.
    multi : bool
        The scenario has several sensors.
    **options
        Further keyword arguments of the filter's class.

    Returns
    -------
    Filter

    Raises
    ------
    TypeError
        If ``filter`` is none of these, or an object is given with an association or options.
    ValueError
        On an unknown name.

    Examples
    --------
    >>> from rankedassign.tracking import Exact, make_model
    >>> type(make_filter("glmb", make_model("vo"), Exact(), multi=False)).__name__
    'GLMBFilter'
    """
    if not isinstance(filter, (str, type)):
        if not isinstance(filter, Filter):
            raise TypeError(f"filter must be one of {tuple(FILTERS)}, a filter class or a "
                            "filter object with methods reset() and step(scan, rng), got "
                            f"{type(filter).__name__}")
        if association is not None or options:
            raise TypeError("a filter object runs as it is: pass its association and options "
                            "to its class, not to the runner (or pass the class)")
        return filter
    entry = _entry(filter)
    cls = filter if entry is None else (entry.multi if multi else entry.single)
    if association is None:
        raise TypeError("the runner needs an association for the filter, e.g. "
                        "ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)")
    return cls(model, association, **options)

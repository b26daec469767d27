"""One vocabulary for the studies: a truncation is named by its association class's ``name``.

The studies grew their own spellings of the same sampler (``"long"``, ``"gibbs"`` for
:class:`~rankedassign.tracking.OriginalGibbs`, ``"short"`` for
:class:`~rankedassign.tracking.ShortChainGibbs`). A study names a truncation by the class's
``name`` (:data:`TRUNCATIONS`); :func:`canonical_truncation` reads an old spelling from a
``--config`` file as the new name, with a :class:`DeprecationWarning` that names it
(:data:`DEPRECATED_TRUNCATIONS`, listed in the changelog, ``docs/structure.md``).

``method`` means only the multi-sensor row conditional (``"exact"``, ``"mm"``, ``"mm-fixed"``,
``"componentwise"``: :data:`ROW_METHODS`). Two studies packed a filter, a truncation and a row
conditional into one string (``"short-mm"``, ``"glmb-long"``); they now name a cell by a pair
of names, and :func:`canonical_pair` reads an old string as its pair, with the same warning
(:data:`DEPRECATED_ASSOCIATIONS`, :data:`DEPRECATED_FILTER_TRUNCATIONS`).
"""

from __future__ import annotations

import json
import warnings

from .. import tracking
from ..multisensor.prepare import METHODS as ROW_METHODS

__all__ = ["TRUNCATIONS", "DEPRECATED_TRUNCATIONS", "canonical_truncation", "ROW_METHODS",
           "DEPRECATED_ASSOCIATIONS", "DEPRECATED_FILTER_TRUNCATIONS",
           "DEPRECATED_GLMB_TRUNCATIONS", "DEPRECATED_TRACKING_SAMPLERS", "canonical_pair",
           "canonical_value"]

#: Every truncation, by its association class's ``name``.
TRUNCATIONS = tuple(cls.name for cls in (
    tracking.OriginalGibbs, tracking.ShortChainGibbs, tracking.HerdedGibbs,
    tracking.TemperedGibbs, tracking.Murty, tracking.Exact, tracking.LBP))
#: Old spellings of a truncation in the studies' settings, and the name that replaces each.
DEPRECATED_TRUNCATIONS = {"long": tracking.OriginalGibbs.name,
                          "gibbs": tracking.OriginalGibbs.name,
                          "short": tracking.ShortChainGibbs.name}
#: The ``multisensor_tracking`` study's old association strings (its ``methods``,
#: ``adaptive_methods``, ``glmb_methods``) and the ``(truncation, method)`` pair each stands for:
#: the truncation by its class's name, ``method`` the row conditional it always ran with
#: (``"exact"`` of the exact DP: its long-chain fallback's).
DEPRECATED_ASSOCIATIONS = {
    "long": (tracking.OriginalGibbs.name, "exact"),
    "short": (tracking.ShortChainGibbs.name, "exact"),
    "short-mm": (tracking.ShortChainGibbs.name, "mm"),
    "short-mm-fixed": (tracking.ShortChainGibbs.name, "mm-fixed"),
    "exact": (tracking.Exact.name, "exact"),
}
#: The ``glmb_tracking`` study's old method strings (decoded by ``split("-")``) and the
#: ``(filter, truncation)`` pair each stands for (``"murty-matched"``: the study's Murty whose
#: ``H_upd`` is matched to the short chains' hypotheses, a rule of that study, not a class).
DEPRECATED_FILTER_TRUNCATIONS = {
    f"{f}-{old}": (f, new)
    for f, olds in (("lmb", ("exact", "long", "short", "murty")),
                    ("glmb", ("exact", "long", "short", "murty", "murty-matched", "herded")))
    for old, new in ((o, {"long": tracking.OriginalGibbs.name,
                          "short": tracking.ShortChainGibbs.name}.get(o, o)) for o in olds)
}
#: The ``tracking`` study's old name of its short chains (the paper's "proposed" sampler), in
#: its per-run records' ``truncation`` and its task's argument.
DEPRECATED_TRACKING_SAMPLERS = {"proposed": tracking.ShortChainGibbs.name}
#: The ``glmb_tracking`` study's old ``tradeoff_methods`` (all δ-GLMB) and the truncation each
#: stands for.
DEPRECATED_GLMB_TRUNCATIONS = {old: t for old, (f, t) in DEPRECATED_FILTER_TRUNCATIONS.items()
                               if f == "glmb"}


def canonical_truncation(value, setting: str):
    """The truncation name ``value`` stands for: itself, or the name of a deprecated spelling.

    Parameters
    ----------
    value : object
        A setting's value as read (checked against the study's choices afterwards).
    setting : str
        The setting's name, for the warning.

    Returns
    -------
    object
        ``value``, or for a key of :data:`DEPRECATED_TRUNCATIONS` the name that replaces it.

    Warns
    -----
    DeprecationWarning
        For a deprecated spelling, naming the new one.

    Examples
    --------
    >>> canonical_truncation("murty", "truncations")
    'murty'
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     new = canonical_truncation("short", "truncations")
    >>> new
    'short-chain'
    >>> print(w[0].message)
    truncations: 'short' is deprecated; write 'short-chain' (the ShortChainGibbs class's name)
    """
    new = DEPRECATED_TRUNCATIONS.get(value) if isinstance(value, str) else None
    if new is None:
        return value
    cls = next(c for c in (tracking.OriginalGibbs, tracking.ShortChainGibbs) if c.name == new)
    warnings.warn(f"{setting}: {value!r} is deprecated; write {new!r} (the {cls.__name__} "
                  "class's name)", DeprecationWarning, stacklevel=3)
    return new


def canonical_pair(value, setting: str, deprecated: dict, *, truncation_at: int = 0):
    """The pair ``value`` stands for: itself as a tuple, or the pair of a deprecated string.

    A study whose cell is a pair of names (``(truncation, method)`` in ``multisensor_tracking``,
    ``(filter, truncation)`` in ``glmb_tracking``) reads it from a ``--config`` file as a
    two-element list; the old one-string spelling of the same cell still reads, deprecated.

    Parameters
    ----------
    value : object
        A setting's entry as read (checked against the study's choices afterwards).
    setting : str
        The setting's name, for the warning.
    deprecated : dict
        Old strings and their pairs (:data:`DEPRECATED_ASSOCIATIONS`,
        :data:`DEPRECATED_FILTER_TRUNCATIONS`).
    truncation_at : {0, 1}, optional
        Which name of a pair is the truncation (0: ``(truncation, method)``; 1:
        ``(filter, truncation)``).

    Returns
    -------
    object
        A list or tuple of two as a tuple, its truncation through
        :func:`canonical_truncation`; for a key of ``deprecated`` its pair; any other value
        unchanged.

    Warns
    -----
    DeprecationWarning
        For a deprecated string, naming the pair that replaces it (as a ``--config`` file
        writes it).

    Examples
    --------
    >>> canonical_pair(["short-chain", "mm"], "methods", DEPRECATED_ASSOCIATIONS)
    ('short-chain', 'mm')
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     new = canonical_pair("glmb-long", "methods", DEPRECATED_FILTER_TRUNCATIONS,
    ...                          truncation_at=1)
    >>> new
    ('glmb', 'original')
    >>> print(w[0].message)
    methods: 'glmb-long' is deprecated; write ["glmb", "original"]
    """
    if isinstance(value, (list, tuple)):
        value = list(value)
        if len(value) == 2:  # a deprecated truncation spelling inside a pair
            value[truncation_at] = canonical_truncation(value[truncation_at], setting)
        return tuple(value)
    return canonical_value(value, setting, deprecated, stacklevel=4)


def canonical_value(value, setting: str, deprecated: dict, *, stacklevel: int = 3):
    """``deprecated[value]`` with a warning naming it, for a deprecated string; else ``value``.

    Parameters
    ----------
    value : object
        A setting's entry as read.
    setting : str
        The setting's name, for the warning.
    deprecated : dict
        Old strings and what replaces each: a name, or a pair of names.
    stacklevel : int, optional
        Passed on to ``warnings.warn`` (3: the caller of the function that calls this).

    Returns
    -------
    object
        The replacement, or ``value`` unchanged.

    Warns
    -----
    DeprecationWarning
        ``"<setting>: '<old>' is deprecated; write <new>"``, a pair written as the JSON list a
        ``--config`` file holds.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     new = canonical_value("glmb-short", "tradeoff_methods", DEPRECATED_GLMB_TRUNCATIONS)
    >>> new, str(w[0].message)
    ('short-chain', "tradeoff_methods: 'glmb-short' is deprecated; write 'short-chain'")
    """
    new = deprecated.get(value) if isinstance(value, str) else None
    if new is None:
        return value
    shown = json.dumps(list(new)) if isinstance(new, tuple) else repr(new)
    warnings.warn(f"{setting}: {value!r} is deprecated; write {shown}", DeprecationWarning,
                  stacklevel=stacklevel)
    return new

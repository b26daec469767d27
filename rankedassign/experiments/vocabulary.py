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

``tempering_herding`` runs several variants of one class (herded keys, herded short chains,
β values, the Zanella–Roberts scheme): it names each by a ``(truncation, variant)`` pair, the
variant the class's settings written out (``("herded", "keys=full")``,
``("tempered", "scheme=zanella-roberts")``, ``""`` for none), and :func:`canonical_variant`
reads its old strings (``"herded-full"``, ``"beta-0.5"``) as their pairs
(:data:`DEPRECATED_VARIANTS`).
"""

from __future__ import annotations

import json
import warnings

from .. import tracking
from ..multisensor.prepare import METHODS as ROW_METHODS

__all__ = ["TRUNCATIONS", "DEPRECATED_TRUNCATIONS", "canonical_truncation", "ROW_METHODS",
           "DEPRECATED_ASSOCIATIONS", "DEPRECATED_FILTER_TRUNCATIONS",
           "DEPRECATED_GLMB_TRUNCATIONS", "DEPRECATED_TRACKING_SAMPLERS", "canonical_pair",
           "canonical_value", "variant", "DEPRECATED_VARIANTS", "PLAIN_TRUNCATIONS",
           "canonical_variant"]

#: Every truncation, by its association class's ``name``.
TRUNCATIONS = tuple(cls.name for cls in (
    tracking.OriginalGibbs, tracking.ShortChainGibbs, tracking.HerdedGibbs,
    tracking.TemperedGibbs, tracking.Murty, tracking.Exact, tracking.LBP))
#: Old spellings of a truncation in the studies' settings, and the name that replaces each.
DEPRECATED_TRUNCATIONS = {"long": tracking.OriginalGibbs.name,
                          "gibbs": tracking.OriginalGibbs.name,
                          "short": tracking.ShortChainGibbs.name}
#: The ``multisensor_tracking`` study's old association strings (its ``associations``,
#: ``adaptive_associations``, ``glmb_associations``, formerly ``*methods``) and the
#: ``(truncation, method)`` pair each stands for: the truncation by its class's name,
#: ``method`` the row conditional it always ran with (``"exact"`` of the exact DP: its
#: long-chain fallback's).
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
#: The ``glmb_tracking`` study's old ``tradeoff_truncations`` (all δ-GLMB; the setting was
#: ``tradeoff_methods``) and the truncation each stands for.
DEPRECATED_GLMB_TRUNCATIONS = {old: t for old, (f, t) in DEPRECATED_FILTER_TRUNCATIONS.items()
                               if f == "glmb"}


def variant(**settings) -> str:
    """A variant's name: its class settings written out, ``key=value`` joined by commas.

    Parameters
    ----------
    **settings
        The settings that tell the variant from the class's defaults, in the order they are
        written (``chains``, ``keys``; ``beta``; ``scheme``).

    Returns
    -------
    str
        ``""`` for none.

    Examples
    --------
    >>> variant(chains="short", keys="full"), variant(beta=0.5), variant()
    ('chains=short,keys=full', 'beta=0.5', '')
    """
    return ",".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                    for k, v in settings.items())


#: The ``tempering_herding`` study's old method strings (its ``truncations`` and
#: ``tracking_truncations``, formerly ``methods`` and ``tracking_methods``) and the
#: ``(truncation, variant)`` pair each stands for: one herded chain (``"herded"`` of the
#: tracking part: shared keys), herded short chains (``"short"`` chains), a β-chain, the
#: Zanella–Roberts scheme (its β is the study's ``zr_beta``).
DEPRECATED_VARIANTS = {
    "herded-shared": (tracking.HerdedGibbs.name, variant(keys="shared")),
    "herded-full": (tracking.HerdedGibbs.name, variant(keys="full")),
    "herded-short-shared": (tracking.HerdedGibbs.name, variant(chains="short", keys="shared")),
    "herded-short-full": (tracking.HerdedGibbs.name, variant(chains="short", keys="full")),
    **{f"beta-{b}": (tracking.TemperedGibbs.name, variant(beta=float(b)))
       for b in ("0.5", "0.7", "0.9")},
    "zanella-roberts": (tracking.TemperedGibbs.name, variant(scheme="zanella-roberts")),
    "herded": (tracking.HerdedGibbs.name, variant(keys="shared")),
    "herded-short": (tracking.HerdedGibbs.name, variant(chains="short", keys="shared")),
}
#: Truncations that ``tempering_herding`` runs without a variant: a ``--config`` file may name
#: one alone (``"lbp"`` for ``["lbp", ""]``).
PLAIN_TRUNCATIONS = (tracking.OriginalGibbs.name, tracking.ShortChainGibbs.name,
                     tracking.Exact.name, tracking.LBP.name)


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
    >>> canonical_pair(["short-chain", "mm"], "associations", DEPRECATED_ASSOCIATIONS)
    ('short-chain', 'mm')
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     new = canonical_pair("glmb-long", "filter_truncations",
    ...                          DEPRECATED_FILTER_TRUNCATIONS, truncation_at=1)
    >>> new
    ('glmb', 'original')
    >>> print(w[0].message)
    filter_truncations: 'glmb-long' is deprecated; write ["glmb", "original"]
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
    ...     new = canonical_value("glmb-short", "tradeoff_truncations",
    ...                           DEPRECATED_GLMB_TRUNCATIONS)
    >>> new, str(w[0].message)
    ('short-chain', "tradeoff_truncations: 'glmb-short' is deprecated; write 'short-chain'")
    """
    new = deprecated.get(value) if isinstance(value, str) else None
    if new is None:
        return value
    shown = json.dumps(list(new)) if isinstance(new, tuple) else repr(new)
    warnings.warn(f"{setting}: {value!r} is deprecated; write {shown}", DeprecationWarning,
                  stacklevel=stacklevel)
    return new


def canonical_variant(value, setting: str):
    """The ``(truncation, variant)`` pair ``value`` stands for, in ``tempering_herding``.

    Parameters
    ----------
    value : object
        A ``truncations`` or ``tracking_truncations`` entry as read (checked against the study's
        choices afterwards).
    setting : str
        The setting's name, for the warning.

    Returns
    -------
    object
        A list or tuple of two as a tuple (a deprecated truncation spelling in it replaced);
        the name of a truncation without variants (:data:`PLAIN_TRUNCATIONS`) as
        ``(name, "")``; for a key of :data:`DEPRECATED_VARIANTS` its pair; any other value
        unchanged.

    Warns
    -----
    DeprecationWarning
        For an old string, naming the pair that replaces it (as a ``--config`` file writes it),
        and for ``"gibbs"``, ``"short"`` (:func:`canonical_truncation`).

    Examples
    --------
    >>> canonical_variant("lbp", "truncations")
    ('lbp', '')
    >>> canonical_variant(["herded", "keys=full"], "truncations")
    ('herded', 'keys=full')
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     new = canonical_variant("herded-short-full", "truncations")
    >>> new
    ('herded', 'chains=short,keys=full')
    >>> print(w[0].message)
    truncations: 'herded-short-full' is deprecated; write ["herded", "chains=short,keys=full"]
    """
    if isinstance(value, (list, tuple)):
        return canonical_pair(value, setting, {})
    if isinstance(value, str) and value in DEPRECATED_TRUNCATIONS:
        value = canonical_truncation(value, setting)
    if isinstance(value, str) and value in PLAIN_TRUNCATIONS:
        return (value, "")
    return canonical_value(value, setting, DEPRECATED_VARIANTS, stacklevel=4)

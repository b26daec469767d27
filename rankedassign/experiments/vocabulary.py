"""One vocabulary for the studies: a truncation is named by its association class's ``name``.

The studies grew their own spellings of the same sampler (``"long"``, ``"gibbs"`` for
:class:`~rankedassign.tracking.OriginalGibbs`, ``"short"`` for
:class:`~rankedassign.tracking.ShortChainGibbs`). A study names a truncation by the class's
``name`` (:data:`TRUNCATIONS`); :func:`canonical_truncation` reads an old spelling from a
``--config`` file as the new name, with a :class:`DeprecationWarning` that names it
(:data:`DEPRECATED_TRUNCATIONS`, listed in the changelog, ``docs/structure.md``).
"""

from __future__ import annotations

import warnings

from .. import tracking

__all__ = ["TRUNCATIONS", "DEPRECATED_TRUNCATIONS", "canonical_truncation"]

#: Every truncation, by its association class's ``name``.
TRUNCATIONS = tuple(cls.name for cls in (
    tracking.OriginalGibbs, tracking.ShortChainGibbs, tracking.HerdedGibbs,
    tracking.TemperedGibbs, tracking.Murty, tracking.Exact, tracking.LBP))
#: Old spellings of a truncation in the studies' settings, and the name that replaces each.
DEPRECATED_TRUNCATIONS = {"long": tracking.OriginalGibbs.name,
                          "gibbs": tracking.OriginalGibbs.name,
                          "short": tracking.ShortChainGibbs.name}


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

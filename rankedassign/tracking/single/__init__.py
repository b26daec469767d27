"""The single-sensor LMB filter and its association methods.

* :mod:`~rankedassign.tracking.single.lmb` — :class:`LMBFilter` (spec §6);
* :mod:`~rankedassign.tracking.single.association` — the association methods it takes:
  :class:`OriginalGibbs`, :class:`ShortChainGibbs`, :class:`Murty`, :class:`Exact`.

Everything is re-exported by :mod:`rankedassign.tracking`.
"""

from .association import (
    Association,
    AssociationResult,
    Exact,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    marginals_from_hypotheses,
)
from .lmb import LMBFilter, ScanRecord, gate_threshold, group_tracks, map_cardinality

__all__ = ["Association", "AssociationResult", "Exact", "Murty", "OriginalGibbs",
           "ShortChainGibbs", "marginals_from_hypotheses", "LMBFilter", "ScanRecord",
           "gate_threshold", "group_tracks", "map_cardinality"]

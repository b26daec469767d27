"""The single-sensor LMB and δ-GLMB filters.

* :mod:`~rankedassign.tracking.single.lmb` — :class:`LMBFilter` (spec §6);
* :mod:`~rankedassign.tracking.single.glmb` — :class:`GLMBFilter` (``glmb.md``);
* :mod:`~rankedassign.tracking.single.association` — the old path of the association classes,
  which now live in :mod:`rankedassign.tracking.association` and serve every filter.

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

"""Where the single-sensor associations lived: now :mod:`rankedassign.tracking.association`.

The association classes serve every filter and sensor count
(:mod:`rankedassign.tracking.association`); the marginals from hypotheses are in
:mod:`rankedassign.tracking.marginals`. This module re-exports them under their old path.
"""

from __future__ import annotations

from ..association import (
    LBP,
    MURTY_BACKENDS,
    Association,
    Exact,
    HerdedGibbs,
    LBPConvergenceWarning,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
)
from ..marginals import MARGINALS, AssociationResult, Hypotheses, marginals_from_hypotheses

__all__ = [
    "AssociationResult",
    "Association",
    "Hypotheses",
    "OriginalGibbs",
    "ShortChainGibbs",
    "Murty",
    "Exact",
    "HerdedGibbs",
    "LBP",
    "LBPConvergenceWarning",
    "marginals_from_hypotheses",
    "MARGINALS",
    "MURTY_BACKENDS",
]

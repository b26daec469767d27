"""Where the multi-sensor associations lived: now :mod:`rankedassign.tracking.association`.

:class:`~rankedassign.tracking.OriginalGibbs`, :class:`~rankedassign.tracking.ShortChainGibbs`,
:class:`~rankedassign.tracking.HerdedGibbs` and :class:`~rankedassign.tracking.Exact` serve
multi-sensor problems too (``method=`` is the multi-sensor row conditional). The
``MultiSensor*`` names re-exported here are deprecated aliases for one release
(:mod:`rankedassign.tracking.association` says what they keep); the marginals from
hypotheses are in :mod:`rankedassign.tracking.marginals`.
"""

from __future__ import annotations

from ..association import (
    MULTISENSOR_METHODS,
    MultiSensorAssociation,
    MultiSensorExact,
    MultiSensorHerdedGibbs,
    MultiSensorOriginalGibbs,
    MultiSensorShortChainGibbs,
)
from ..marginals import MultiSensorAssociationResult, multisensor_marginals_from_hypotheses

__all__ = [
    "MULTISENSOR_METHODS",
    "MultiSensorAssociation",
    "MultiSensorAssociationResult",
    "MultiSensorExact",
    "MultiSensorHerdedGibbs",
    "MultiSensorOriginalGibbs",
    "MultiSensorShortChainGibbs",
    "multisensor_marginals_from_hypotheses",
]

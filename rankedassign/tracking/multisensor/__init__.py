"""The multi-sensor LMB and δ-GLMB filters (Vo, Vo & Beard 2019), associations and scenario.

* :mod:`~rankedassign.tracking.multisensor.lmb` — :class:`MultiSensorLMBFilter` and
  :class:`MultiSensorModel`;
* :mod:`~rankedassign.tracking.multisensor.association` — the old path of the deprecated
  ``MultiSensor*`` association names (the classes of :mod:`rankedassign.tracking.association`
  serve every filter and sensor count);
* :mod:`~rankedassign.tracking.multisensor.glmb` — :class:`MultiSensorGLMBFilter`, the
  multi-sensor δ-GLMB filter on the components of the single-sensor one;
* :mod:`~rankedassign.tracking.multisensor.adaptive_birth` — :class:`AdaptiveBirth`, births
  from the adaptive-birth sampler;
* :mod:`~rankedassign.tracking.multisensor.scenario` — the ``"multi"`` scenario (its runner,
  :func:`~rankedassign.tracking.run.run_multisensor_scenario`, lives above the filters).

Its δ-GLMB filter extends the single-sensor one's public class
(:class:`~rankedassign.tracking.GLMBFilter`); what both folders share otherwise lives in
:mod:`rankedassign.tracking.common`. Everything is re-exported by :mod:`rankedassign.tracking`.
"""

from . import scenario
from .adaptive_birth import AdaptiveBirth
from .association import (
    MultiSensorAssociation,
    MultiSensorAssociationResult,
    MultiSensorExact,
    MultiSensorHerdedGibbs,
    MultiSensorOriginalGibbs,
    MultiSensorShortChainGibbs,
)
from .glmb import MultiSensorGLMBFilter
from .lmb import MultiSensorLMBFilter, MultiSensorModel
from .scenario import MultiSensorRun, make_multisensor_model, make_multisensor_scenario

__all__ = ["AdaptiveBirth", "MultiSensorAssociation", "MultiSensorAssociationResult",
           "MultiSensorExact", "MultiSensorHerdedGibbs", "MultiSensorOriginalGibbs",
           "MultiSensorShortChainGibbs",
           "MultiSensorGLMBFilter", "MultiSensorLMBFilter", "MultiSensorModel", "MultiSensorRun",
           "make_multisensor_model", "make_multisensor_scenario"]


def __getattr__(name: str):
    # run_multisensor_scenario moved to rankedassign.tracking.run (above the filters); the
    # old path warns for one release
    if name == "run_multisensor_scenario":
        return scenario.__getattr__(name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

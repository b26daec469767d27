"""The LMB and δ-GLMB filters of the tracking study, their models, scenario and associations.

Quick start::

    from rankedassign.tracking import ShortChainGibbs, run_scenario
    from rankedassign.metrics import ospa2

    run = run_scenario("paper", ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), rng=0)
    curve = ospa2(run.truth, run.estimates, c=200, p=1, window=5).value

See spec §6 (filter), §7 (OSPA(2)) and §8 (truth).
"""

from .adaptive_birth import AdaptiveBirth
from .association import (
    Association,
    AssociationResult,
    Exact,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    marginals_from_hypotheses,
)
from .glmb import GLMBFilter, GLMBScanRecord, Hypotheses
from .lmb import LMBFilter, ScanRecord, gate_threshold, group_tracks, map_cardinality
from .models import (
    PRESET_EXTRACTION,
    BirthComponent,
    ConstantSurvival,
    ConstantVelocity,
    LMBBirth,
    Model,
    PoissonClutter,
    PositionSensor,
    make_model,
)
from .multisensor import MultiSensorLMBFilter, MultiSensorModel
from .multisensor_association import (
    MultiSensorAssociationResult,
    MultiSensorExact,
    MultiSensorGibbs,
    MultiSensorShortChains,
)
from .multisensor_scenario import (
    MultiSensorRun,
    make_multisensor_model,
    make_multisensor_scenario,
    run_multisensor_scenario,
)
from .run import ScenarioRun, run_scenario
from .scenario import Scan, Scenario, Truth, generate_measurements, make_scenario, paper_truth

__all__ = [
    "AdaptiveBirth",
    "Association",
    "AssociationResult",
    "BirthComponent",
    "ConstantSurvival",
    "ConstantVelocity",
    "Exact",
    "GLMBFilter",
    "GLMBScanRecord",
    "Hypotheses",
    "LMBBirth",
    "LMBFilter",
    "Model",
    "Murty",
    "MultiSensorAssociationResult",
    "MultiSensorExact",
    "MultiSensorGibbs",
    "MultiSensorLMBFilter",
    "MultiSensorModel",
    "MultiSensorRun",
    "MultiSensorShortChains",
    "OriginalGibbs",
    "PRESET_EXTRACTION",
    "PoissonClutter",
    "PositionSensor",
    "Scan",
    "ScanRecord",
    "Scenario",
    "ScenarioRun",
    "ShortChainGibbs",
    "Truth",
    "gate_threshold",
    "generate_measurements",
    "group_tracks",
    "make_model",
    "make_multisensor_model",
    "make_multisensor_scenario",
    "make_scenario",
    "map_cardinality",
    "marginals_from_hypotheses",
    "paper_truth",
    "run_multisensor_scenario",
    "run_scenario",
]

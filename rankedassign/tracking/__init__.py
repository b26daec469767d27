"""The LMB and δ-GLMB filters of the tracking study, their models, scenario and associations.

Quick start::

    from rankedassign.tracking import ShortChainGibbs, run_scenario
    from rankedassign.metrics import ospa2

    run = run_scenario("paper", ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), rng=0)
    curve = ospa2(run.truth, run.estimates, c=200, p=1, window=5).value

On one's own measurements (a CSV with columns ``scan, x, y``)::

    from rankedassign.tracking import LMBFilter, make_model, read_measurements, run_filter

    lmb = LMBFilter(make_model("vo"), ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10))
    run = run_filter(lmb, read_measurements("measurements.csv"), rng=0)

See spec §6 (filter), §7 (OSPA(2)) and §8 (truth).
"""

from .association import (
    LBP,
    Association,
    Exact,
    HerdedGibbs,
    LBPConvergenceWarning,
    MultiSensorExact,
    MultiSensorHerdedGibbs,
    MultiSensorOriginalGibbs,
    MultiSensorShortChainGibbs,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    TemperedGibbs,
    check_truncation,
    truncate,
)
from .birth import MeasurementBirth
from .clustered import ClusteredGLMBFilter, ClusteredScanRecord
from .common import gate_threshold
from .filters import FILTERS, make_filter
from .io import read_measurements, write_measurements
from .marginals import (
    AssociationResult,
    Hypotheses,
    MultiSensorAssociationResult,
    marginals_from_hypotheses,
    multisensor_marginals_from_hypotheses,
)
from .models import (
    PRESET_EXTRACTION,
    BirthComponent,
    ConstantSurvival,
    ConstantVelocity,
    LinearMotion,
    LMBBirth,
    Model,
    PoissonClutter,
    PositionSensor,
)
from .multisensor.adaptive_birth import AdaptiveBirth
from .multisensor.glmb import MultiSensorGLMBFilter
from .multisensor.lmb import MultiSensorLMBFilter, MultiSensorModel
from .multisensor.scenario import (
    MultiSensorRun,
    make_multisensor_model,
    make_multisensor_scenario,
)
from .presets import make_model, make_scenario
from .protocol import Filter
from .run import ScenarioRun, run_multisensor_scenario, run_scenario
from .runner import FilterRun, run_filter
from .scenario import Scan, Scenario, Truth, generate_measurements, paper_truth
from .single.glmb import GLMB_EXTRACTIONS, GLMBFilter, GLMBScanRecord
from .single.lmb import LMBFilter, ScanRecord, group_tracks, map_cardinality

__all__ = [
    "AdaptiveBirth",
    "Association",
    "AssociationResult",
    "BirthComponent",
    "ClusteredGLMBFilter",
    "ClusteredScanRecord",
    "ConstantSurvival",
    "ConstantVelocity",
    "Exact",
    "FilterRun",
    "HerdedGibbs",
    "TemperedGibbs",
    "LBP",
    "LBPConvergenceWarning",
    "GLMB_EXTRACTIONS",
    "GLMBFilter",
    "GLMBScanRecord",
    "Hypotheses",
    "LMBBirth",
    "LinearMotion",
    "LMBFilter",
    "MeasurementBirth",
    "Model",
    "Murty",
    "MultiSensorAssociationResult",
    "MultiSensorExact",
    "MultiSensorHerdedGibbs",
    "MultiSensorOriginalGibbs",
    "MultiSensorGLMBFilter",
    "MultiSensorLMBFilter",
    "MultiSensorModel",
    "MultiSensorRun",
    "MultiSensorShortChainGibbs",
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
    "read_measurements",
    "run_filter",
    "run_multisensor_scenario",
    "run_scenario",
    "write_measurements",
    "check_truncation",
    "truncate",
    "FILTERS",
    "Filter",
    "make_filter",
    "multisensor_marginals_from_hypotheses",
]

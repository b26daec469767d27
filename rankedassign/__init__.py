"""rankedassign: ranked assignment for labeled random-finite-set trackers.

The ranked-assignment problem of the joint GLMB/LMB prediction/update (Vo, Vo & Hoang 2017),
the original long-chain Gibbs sampler and the short-chain sampler with stall/stale termination
of Trezza, Bucci & Varshney (2023), and OSPA(2). Exact ground truth lives in the companion
package :mod:`oracle`. The LMB filter with pluggable association, :mod:`rankedassign.tracking`,
builds on both and is imported on its own (``from rankedassign.tracking import ...``).
"""

from . import metrics
from ._version import __version__
from .samplers import (
    Herding,
    SamplerResult,
    TemperedResult,
    sample_herded,
    sample_original,
    sample_short_chains,
    sample_tempered,
    warmup,
)
from .single import synthetic
from .single.lbp import LBPResult, lbp_marginals
from .single.problem import AssignmentProblem

__all__ = [
    "AssignmentProblem",
    "SamplerResult",
    "sample_original",
    "sample_short_chains",
    "sample_herded",
    "sample_tempered",
    "TemperedResult",
    "Herding",
    "lbp_marginals",
    "LBPResult",
    "warmup",
    "synthetic",
    "metrics",
    "__version__",
]

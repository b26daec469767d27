"""The oracle of the adaptive-birth kind (:mod:`rankedassign.adaptive_birth`).

:mod:`~oracle.adaptive_birth.exact` enumerates the dense tuple tensor: every tuple best first,
the normaliser, the per-sensor marginals, the truncation error of spec §5 and the exact
one-sweep transition matrix of the sampler. The public entry points are the functions of
:mod:`oracle` (:mod:`oracle.exact`), which call these for an
:class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem`.
"""

from .exact import (
    enumerate_assignments,
    kept_mask,
    log_normalizer,
    marginals,
    transition_matrix,
    truncation_error,
)

__all__ = ["enumerate_assignments", "log_normalizer", "marginals", "truncation_error",
           "kept_mask", "transition_matrix"]

"""The oracle of the multi-sensor kind (:mod:`rankedassign.multisensor`).

* :mod:`~oracle.multisensor.enumerate` — every feasible assignment, best first;
* :mod:`~oracle.multisensor.dp` — the exact normaliser and marginals (a row DP over
  used-measurement masks) and the MM surrogate's normaliser;
* :mod:`~oracle.multisensor.truncation` — the exact truncation error and the best-``k`` mass;
* :mod:`~oracle.multisensor.transition` — the exact one-sweep transition matrices of the
  multi-sensor Gibbs samplers on tiny problems.

The public entry points are the functions of :mod:`oracle` (:mod:`oracle.exact`), which call
these for a :class:`~rankedassign.multisensor.MultiSensorProblem`.
"""

from . import transition
from .dp import MultiSensorMarginals, log_normalizer, marginals, surrogate_log_normalizer
from .enumerate import enumerate_assignments
from .truncation import best_mass, truncation_error

__all__ = ["enumerate_assignments", "log_normalizer", "marginals", "truncation_error",
           "best_mass", "surrogate_log_normalizer", "MultiSensorMarginals", "transition"]
